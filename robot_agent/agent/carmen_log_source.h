#ifndef FLEETMAP_ROBOT_AGENT_AGENT_CARMEN_LOG_SOURCE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_CARMEN_LOG_SOURCE_H_

#include <deque>
#include <memory>
#include <string>

#include "robot_agent/agent/sensor_source.h"
#include "shared/io/carmen_reader.h"

namespace fleetmap {

// Replays a CARMEN log (plain, .gz, .bz2): ODOM lines as odometry, laser lines as scans (with
// their odometry pose), and, when a camera index is given, its frames merged in time order.
class CarmenLogSource : public SensorSource {
 public:
  // `camera_index`: optional file of "timestamp image_path" lines (paths relative to it).
  static std::unique_ptr<CarmenLogSource> Open(const std::string& log_path,
                                               const std::string& camera_index, std::string* error);

  bool Next(SensorEvent* event) override;
  const std::string& error() const override { return error_; }
  std::string Describe() const override { return "CARMEN log " + path_; }

 private:
  CarmenLogSource(std::string path, std::unique_ptr<CarmenReader> reader,
                  std::deque<CameraImage> frames)
      : path_(std::move(path)), reader_(std::move(reader)), frames_(std::move(frames)) {}
  // Reads the next odometry or laser record into `pending_`; false at the end or on error.
  bool FillPending();

  const std::string path_;
  std::unique_ptr<CarmenReader> reader_;
  std::deque<CameraImage> frames_;  // not yet emitted, in time order
  std::optional<SensorEvent> pending_;
  bool log_done_ = false;
  std::string error_;
};

// Reads a camera index: one "timestamp path" per line, '#' comments; sorted by time.
bool ReadCameraIndex(const std::string& path, std::deque<CameraImage>* frames, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_CARMEN_LOG_SOURCE_H_
