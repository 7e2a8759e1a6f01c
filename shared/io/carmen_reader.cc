#include "shared/io/carmen_reader.h"

#include <cmath>
#include <string_view>

#include "shared/io/carmen_parse.h"
#include "shared/io/decompressing_stream.h"

namespace fleetmap {
namespace {

// Distinct unknown message types remembered by name; a garbage file could otherwise fill the
// count map with one entry per line.
constexpr size_t kMaxCountedTypes = 64;

class CarmenFileReader : public CarmenReader {
 public:
  CarmenFileReader(std::string path, std::unique_ptr<DecompressingStream> stream,
                   const CarmenReaderOptions& options)
      : path_(std::move(path)), stream_(std::move(stream)), options_(options) {
    state_.max_range = options.max_range;
  }

  bool Next(CarmenRecord* record) override;
  const std::string& error() const override { return error_; }
  long line_number() const override { return line_number_; }
  long skipped_lines() const override { return skipped_lines_; }
  const std::string& first_skipped_error() const override { return first_skipped_error_; }
  const std::map<std::string, long>& message_counts() const override { return counts_; }

 private:
  // Parses one known message; returns false with `error` for a malformed line, and sets
  // `*produced` when the line yields a record.
  bool ParseLine(std::string_view type, CarmenRecord* record, bool* produced, std::string* error);
  void ApplyParam(const ParamRecord& param, std::string* error);
  void Count(std::string_view type);

  std::string path_;
  std::unique_ptr<DecompressingStream> stream_;
  CarmenReaderOptions options_;
  carmen::LogState state_;
  carmen::Tokens tokens_;
  std::map<std::string, long> counts_;
  std::string error_;
  std::string first_skipped_error_;
  long line_number_ = 0;
  long skipped_lines_ = 0;
  bool done_ = false;
};

void CarmenFileReader::Count(std::string_view type) {
  auto it = counts_.find(std::string(type));
  if (it != counts_.end()) {
    ++it->second;
  } else if (counts_.size() < kMaxCountedTypes) {
    counts_.emplace(std::string(type), 1);
  } else {
    ++counts_["(other)"];
  }
}

void CarmenFileReader::ApplyParam(const ParamRecord& param, std::string* error) {
  const bool offset = param.name == "robot_frontlaser_offset";
  const bool max_range = param.name == "robot_front_laser_max" && options_.max_range_from_params;
  if (!offset && !max_range) return;
  double value;
  if (!carmen::ParseDouble(param.value, &value) || !std::isfinite(value)) {
    *error = "PARAM " + param.name + ": value '" + param.value + "' is not a finite number";
    return;
  }
  if (offset) {
    state_.has_frontlaser_offset = true;
    state_.frontlaser_offset = value;
  } else if (value > 0.0) {
    state_.max_range = value;
  } else {
    *error = "PARAM " + param.name + ": value must be positive";
  }
}

bool CarmenFileReader::ParseLine(std::string_view type, CarmenRecord* record, bool* produced,
                                 std::string* error) {
  *produced = false;
  if (type == "FLASER" || type == "ROBOTLASER1") {
    LaserRecord laser;
    const bool ok =
        type == "FLASER"
            ? carmen::ParseFlaser(tokens_, state_, options_.max_beams, &laser, error)
            : carmen::ParseRobotLaser(tokens_, state_, options_.max_beams, &laser, error);
    if (!ok) return false;
    *record = std::move(laser);
  } else if (type == "ODOM") {
    OdometryRecord odometry;
    if (!carmen::ParseOdometry(tokens_, &odometry, error)) return false;
    *record = odometry;
  } else if (type == "PARAM") {
    ParamRecord param;
    if (!carmen::ParseParam(tokens_, &param, error)) return false;
    ApplyParam(param, error);
    if (!error->empty()) return false;
    *record = std::move(param);
  } else {
    return true;  // unknown message types are skipped
  }
  *produced = true;
  return true;
}

bool CarmenFileReader::Next(CarmenRecord* record) {
  if (done_) return false;
  std::string_view line;
  while (stream_->NextLine(&line)) {
    ++line_number_;
    carmen::SplitTokens(line, &tokens_);
    if (tokens_.empty()) continue;
    if (tokens_[0][0] == '#') {
      Count("#");
      continue;
    }
    Count(tokens_[0]);
    std::string message;
    bool produced = false;
    if (ParseLine(tokens_[0], record, &produced, &message)) {
      if (produced) return true;
      continue;
    }
    message = path_ + ":" + std::to_string(line_number_) + ": " + message;
    if (!options_.skip_bad_lines) {
      error_ = message;
      done_ = true;
      return false;
    }
    if (skipped_lines_ == 0) first_skipped_error_ = message;
    ++skipped_lines_;
  }
  done_ = true;
  if (!stream_->error().empty()) {
    error_ = path_ + ":" + std::to_string(line_number_ + 1) + ": " + stream_->error();
  }
  return false;
}

}  // namespace

const std::map<std::string, long>& CarmenReader::message_counts() const {
  static const std::map<std::string, long> kNone;
  return kNone;
}

std::unique_ptr<CarmenReader> CarmenReader::Open(const std::string& path,
                                                 const CarmenReaderOptions& options,
                                                 std::string* error) {
  std::string open_error;
  std::unique_ptr<DecompressingStream> stream = DecompressingStream::Open(path, &open_error);
  if (!stream) {
    if (error) *error = open_error;
    return nullptr;
  }
  if (options.max_beams < 0 || !(options.max_range > 0.0)) {
    if (error) *error = "CarmenReaderOptions: max_beams must be >= 0 and max_range > 0";
    return nullptr;
  }
  return std::make_unique<CarmenFileReader>(path, std::move(stream), options);
}

}  // namespace fleetmap
