#include "robot_agent/agent/carmen_log_source.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

namespace fleetmap {

bool ReadCameraIndex(const std::string& path, std::deque<CameraImage>* frames, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot read the camera index";
    return false;
  }
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    CameraImage frame;
    std::string image;
    if (!(fields >> frame.timestamp)) {
      std::istringstream probe(line);
      std::string first;
      if (!(probe >> first) || first[0] == '#') continue;  // blank or comment
      *error = path + ":" + std::to_string(number) + ": expected 'timestamp image_path'";
      return false;
    }
    if (!(fields >> image) || !std::isfinite(frame.timestamp)) {
      *error = path + ":" + std::to_string(number) + ": expected 'timestamp image_path'";
      return false;
    }
    frame.path = std::filesystem::path(image).is_absolute() ? image : (dir / image).string();
    frames->push_back(std::move(frame));
  }
  std::stable_sort(frames->begin(), frames->end(), [](const CameraImage& a, const CameraImage& b) {
    return a.timestamp < b.timestamp;
  });
  return true;
}

std::unique_ptr<CarmenLogSource> CarmenLogSource::Open(const std::string& log_path,
                                                       const std::string& camera_index,
                                                       std::string* error) {
  std::deque<CameraImage> frames;
  if (!camera_index.empty() && !ReadCameraIndex(camera_index, &frames, error)) return nullptr;
  std::unique_ptr<CarmenReader> reader = CarmenReader::Open(log_path, CarmenReaderOptions(), error);
  if (!reader) return nullptr;
  return std::unique_ptr<CarmenLogSource>(
      new CarmenLogSource(log_path, std::move(reader), std::move(frames)));
}

bool CarmenLogSource::FillPending() {
  CarmenRecord record;
  while (!log_done_ && !pending_) {
    if (!reader_->Next(&record)) {
      log_done_ = true;
      if (!reader_->error().empty()) error_ = reader_->error();
      break;
    }
    if (const auto* odometry = std::get_if<OdometryRecord>(&record)) {
      SensorEvent event;
      event.timestamp = odometry->timestamp;
      event.odometry = *odometry;
      pending_ = std::move(event);
    } else if (auto* laser = std::get_if<LaserRecord>(&record)) {
      SensorEvent event;
      event.timestamp = laser->scan.timestamp;
      event.laser = std::move(*laser);
      pending_ = std::move(event);
    }  // PARAM lines carry nothing the agent needs.
  }
  return pending_.has_value();
}

bool CarmenLogSource::Next(SensorEvent* event) {
  if (!error_.empty()) return false;
  FillPending();
  if (!error_.empty()) return false;
  // A frame goes first when it is not later than the next record.
  if (!frames_.empty() && (!pending_ || frames_.front().timestamp <= pending_->timestamp)) {
    *event = SensorEvent();
    event->timestamp = frames_.front().timestamp;
    event->camera = std::move(frames_.front());
    frames_.pop_front();
    return true;
  }
  if (!pending_) return false;
  *event = std::move(*pending_);
  pending_.reset();
  return true;
}

}  // namespace fleetmap
