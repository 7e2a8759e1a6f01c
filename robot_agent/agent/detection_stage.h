#ifndef FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_STAGE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_STAGE_H_

#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "robot_agent/agent/sensor_source.h"
#include "robot_agent/detection/robot_detector.h"
#include "shared/core/robot_detection.h"

namespace fleetmap {

// What the detector needs to know about this robot's camera, the markers and the scanner. The
// simulator supplies it from its scenario (sim_detection_setup.h); a log from the configuration.
struct DetectionSetup {
  CameraModel camera;
  MarkerGeometry geometry;
  ColourModel colours;  // one marker per robot; its robot_id is the marker's name
  double laser_range_noise = 0.01;
};

struct DetectionStageOptions {
  std::string observer_id;
  double max_time_difference = 0.05;             // seconds between a frame and its scan
  std::map<std::string, std::string> robot_ids;  // marker name -> robot id, when they differ
  RobotDetectorOptions detector;
};

// Counters, readable from other threads (status lines).
struct DetectionCounters {
  std::atomic<int64_t> frames{0};           // camera frames seen
  std::atomic<int64_t> unpaired_frames{0};  // no scan close enough in time
  std::atomic<int64_t> unusable_frames{0};  // unreadable file, wrong size
  std::atomic<int64_t> detections{0};       // laser-confirmed sightings of other robots
};

// Camera frames + laser scans -> RobotDetections: pairs each frame with the scan nearest in
// time (a frame may come before or after its scan, so frames wait until a later scan arrives),
// then runs the RobotDetector (image candidates, laser confirmation and circle fit). The result
// is the seen robot's centre in this robot's frame at the scan's time, with its covariance.
class DetectionStage {
 public:
  // nullptr + `error` when the camera, geometry or colour model is unusable.
  static std::unique_ptr<DetectionStage> Create(const DetectionSetup& setup,
                                                const DetectionStageOptions& options,
                                                std::string* error);

  // Feeds one sensor event; appends the detections that became ready. Bad frames are counted
  // and skipped (last_problem() says why), never fatal.
  void Process(const SensorEvent& event, std::vector<RobotDetection>* detections);
  // End of input: frames still waiting are paired with the best scan there is.
  void Finish(std::vector<RobotDetection>* detections);

  const DetectionCounters& counters() const { return counters_; }
  const std::string& last_problem() const { return last_problem_; }

 private:
  DetectionStage(std::unique_ptr<RobotDetector> detector, const DetectionStageOptions& options);
  void DetectInFrame(const CameraImage& frame, std::vector<RobotDetection>* detections);
  const LaserScan* NearestScan(double timestamp) const;

  const std::unique_ptr<RobotDetector> detector_;
  const DetectionStageOptions options_;
  std::deque<LaserScan> scans_;      // recent scans, time order
  std::deque<CameraImage> waiting_;  // frames newer than the newest scan
  DetectionCounters counters_;
  std::string last_problem_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_DETECTION_STAGE_H_
