#include "robot_agent/detection/robot_detector.h"

#include <utility>

namespace fleetmap {

std::unique_ptr<RobotDetector> RobotDetector::Create(const CameraModel& camera,
                                                     const MarkerGeometry& geometry,
                                                     const ColourModel& colours,
                                                     const RobotDetectorOptions& options,
                                                     std::string* error) {
  std::unique_ptr<MarkerDetector> marker_detector =
      MarkerDetector::Create(camera, geometry, colours, options.image, error);
  if (!marker_detector) return nullptr;
  if (!(options.laser.range_noise > 0.0) || options.laser.min_returns < 2) {
    *error = "laser fusion needs range_noise > 0 and min_returns >= 2";
    return nullptr;
  }
  return std::unique_ptr<RobotDetector>(
      new RobotDetector(std::move(marker_detector), geometry, options.laser));
}

RobotDetector::RobotDetector(std::unique_ptr<MarkerDetector> marker_detector,
                             const MarkerGeometry& geometry,
                             const LaserFusionOptions& laser_options)
    : marker_detector_(std::move(marker_detector)),
      geometry_(geometry),
      laser_options_(laser_options) {}

bool RobotDetector::Detect(const BgrImageView& image, const LaserScan& scan,
                           const std::string& observer_id, FrameDetections* result,
                           std::string* error) const {
  result->detections.clear();
  result->statuses.clear();
  if (!marker_detector_->Detect(image, &result->candidates, error)) return false;
  for (const MarkerCandidate& candidate : result->candidates) {
    FusionResult fused = FuseWithLaser(candidate, scan, marker_detector_->camera(), geometry_,
                                       laser_options_);
    result->statuses.push_back(fused.status);
    if (fused.status != FusionStatus::kConfirmed) continue;
    fused.detection.timestamp = scan.timestamp;
    fused.detection.observer_id = observer_id;
    // A marker split in two by an occluder yields two candidates of one robot: keep the
    // better supported measurement.
    bool merged = false;
    for (RobotDetection& existing : result->detections) {
      if (existing.observed_id != fused.detection.observed_id) continue;
      if (fused.detection.laser_returns > existing.laser_returns) existing = fused.detection;
      merged = true;
    }
    if (!merged) result->detections.push_back(std::move(fused.detection));
  }
  return true;
}

}  // namespace fleetmap
