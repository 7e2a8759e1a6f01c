#include "robot_agent/agent/detection_stage.h"

#include <cmath>
#include <utility>

#include "robot_agent/detection/image_io.h"

namespace fleetmap {
namespace {

// Scans older than the newest by this much can no longer be the nearest to a new frame (frames
// come in time order, give or take the pairing tolerance).
constexpr double kScanHistorySeconds = 2.0;

}  // namespace

std::unique_ptr<DetectionStage> DetectionStage::Create(const DetectionSetup& setup,
                                                       const DetectionStageOptions& options,
                                                       std::string* error) {
  if (!(options.max_time_difference > 0.0)) {
    *error = "detection: max_time_difference must be > 0";
    return nullptr;
  }
  RobotDetectorOptions detector_options = options.detector;
  detector_options.laser.range_noise = setup.laser_range_noise;
  std::string why;
  std::unique_ptr<RobotDetector> detector =
      RobotDetector::Create(setup.camera, setup.geometry, setup.colours, detector_options, &why);
  if (!detector) {
    *error = "detection: " + why;
    return nullptr;
  }
  DetectionStageOptions stored = options;
  stored.detector = detector_options;
  return std::unique_ptr<DetectionStage>(new DetectionStage(std::move(detector), stored));
}

DetectionStage::DetectionStage(std::unique_ptr<RobotDetector> detector,
                               const DetectionStageOptions& options)
    : detector_(std::move(detector)), options_(options) {}

void DetectionStage::Process(const SensorEvent& event, std::vector<RobotDetection>* detections) {
  // The scan first: a frame in the same event is paired with it.
  if (event.laser) {
    const LaserScan& scan = event.laser->scan;
    if (scans_.empty() || scan.timestamp >= scans_.back().timestamp) {
      scans_.push_back(scan);
      while (scans_.front().timestamp < scan.timestamp - kScanHistorySeconds) scans_.pop_front();
    }
    // Frames not later than this scan have met every scan that could be nearest to them.
    while (!waiting_.empty() && waiting_.front().timestamp <= scan.timestamp) {
      DetectInFrame(waiting_.front(), detections);
      waiting_.pop_front();
    }
  }
  if (event.camera) {
    ++counters_.frames;
    if (!scans_.empty() && event.camera->timestamp <= scans_.back().timestamp) {
      DetectInFrame(*event.camera, detections);
    } else {
      waiting_.push_back(*event.camera);
      // A frame can wait at most the pairing tolerance past the newest scan; older frames
      // (e.g. the laser stopped) are paired with what there is.
      while (waiting_.size() > 1 && waiting_.back().timestamp - waiting_.front().timestamp >
                                        options_.max_time_difference + kScanHistorySeconds) {
        DetectInFrame(waiting_.front(), detections);
        waiting_.pop_front();
      }
    }
  }
}

void DetectionStage::Finish(std::vector<RobotDetection>* detections) {
  while (!waiting_.empty()) {
    DetectInFrame(waiting_.front(), detections);
    waiting_.pop_front();
  }
}

const LaserScan* DetectionStage::NearestScan(double timestamp) const {
  const LaserScan* best = nullptr;
  for (const LaserScan& scan : scans_) {
    if (!best || std::abs(scan.timestamp - timestamp) < std::abs(best->timestamp - timestamp)) {
      best = &scan;
    }
  }
  if (!best || std::abs(best->timestamp - timestamp) > options_.max_time_difference) {
    return nullptr;
  }
  return best;
}

void DetectionStage::DetectInFrame(const CameraImage& frame,
                                   std::vector<RobotDetection>* detections) {
  const LaserScan* scan = NearestScan(frame.timestamp);
  if (!scan) {
    ++counters_.unpaired_frames;
    return;
  }
  BgrImage loaded;
  BgrImageView view;
  if (!frame.path.empty() && frame.bgr.empty()) {
    std::string why;
    if (!ReadBgrImage(frame.path, &loaded, &why)) {
      ++counters_.unusable_frames;
      last_problem_ = why;
      return;
    }
    view = loaded.view();
  } else {
    if (frame.bgr.size() != static_cast<size_t>(frame.width) * frame.height * 3) {
      ++counters_.unusable_frames;
      last_problem_ = "camera frame at " + std::to_string(frame.timestamp) +
                      ": pixel buffer does not match its size";
      return;
    }
    view = BgrImageView{frame.bgr.data(), frame.width, frame.height, frame.width * 3, 3};
  }
  FrameDetections found;
  std::string why;
  if (!detector_->Detect(view, *scan, options_.observer_id, &found, &why)) {
    ++counters_.unusable_frames;
    last_problem_ = "camera frame at " + std::to_string(frame.timestamp) + ": " + why;
    return;
  }
  for (RobotDetection& detection : found.detections) {
    const auto renamed = options_.robot_ids.find(detection.observed_id);
    if (renamed != options_.robot_ids.end()) detection.observed_id = renamed->second;
    // The colour model may know this robot's own marker; it never sees itself.
    if (detection.observed_id == options_.observer_id) continue;
    ++counters_.detections;
    detections->push_back(std::move(detection));
  }
}

}  // namespace fleetmap
