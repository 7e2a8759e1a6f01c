#include "shared/io/trajectory_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "shared/io/carmen_parse.h"
#include "shared/io/decompressing_stream.h"

namespace fleetmap {
namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace

bool WriteTrajectory(const std::string& path, const Trajectory& trajectory, std::string* error) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) return Fail(error, path + ": cannot write: " + std::strerror(errno));
  std::fputs("# timestamp x y theta (seconds, metres, radians)\n", file.get());
  for (const StampedPose& stamped : trajectory) {
    std::fprintf(file.get(), "%.6f %.6f %.6f %.9f\n", stamped.timestamp, stamped.pose.x(),
                 stamped.pose.y(), stamped.pose.rotation());
  }
  if (std::fflush(file.get()) != 0 || std::ferror(file.get())) {
    return Fail(error, path + ": write failed: " + std::strerror(errno));
  }
  return true;
}

// Poses are kept in file order, even when timestamps go backwards: raw logs do that (intel has
// 631 laser scans whose ipc_timestamp is earlier than the previous scan's, by up to 0.9 s), and
// the metrics look poses up by time anyway.
bool ReadTrajectory(const std::string& path, Trajectory* trajectory, std::string* error) {
  std::string open_error;
  std::unique_ptr<DecompressingStream> stream = DecompressingStream::Open(path, &open_error);
  if (!stream) return Fail(error, open_error);
  trajectory->clear();
  carmen::Tokens tokens;
  std::string_view line;
  long line_number = 0;
  while (stream->NextLine(&line)) {
    ++line_number;
    carmen::SplitTokens(line, &tokens);
    if (tokens.empty() || tokens[0][0] == '#') continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    if (tokens.size() != 4) {
      return Fail(error, where + "expected 4 values 'timestamp x y theta', found " +
                             std::to_string(tokens.size()));
    }
    double values[4];
    for (int i = 0; i < 4; ++i) {
      if (!carmen::ParseDouble(tokens[static_cast<size_t>(i)], &values[i])) {
        return Fail(error, where + "value " + std::to_string(i + 1) + " '" +
                               std::string(tokens[static_cast<size_t>(i)].substr(0, 20)) +
                               "' is not a number");
      }
      if (!std::isfinite(values[i])) {
        return Fail(error, where + "value " + std::to_string(i + 1) + " is not finite");
      }
    }
    trajectory->push_back(StampedPose{values[0], Rigid2d(values[1], values[2], values[3])});
  }
  if (!stream->error().empty()) {
    return Fail(error, path + ":" + std::to_string(line_number + 1) + ": " + stream->error());
  }
  return true;
}

}  // namespace fleetmap
