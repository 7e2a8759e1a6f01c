#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_ROBOT_DETECTOR_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_ROBOT_DETECTOR_H_

#include <memory>
#include <string>
#include <vector>

#include "robot_agent/detection/detection.h"
#include "robot_agent/detection/image.h"
#include "robot_agent/detection/laser_fusion.h"
#include "robot_agent/detection/marker_detector.h"
#include "shared/core/laser_scan.h"

namespace fleetmap {

struct RobotDetectorOptions {
  MarkerDetectorOptions image;
  LaserFusionOptions laser;
};

// Everything one frame produced, including what was rejected and why (for tools and tests).
struct FrameDetections {
  std::vector<RobotDetection> detections;   // laser-confirmed, at most one per seen robot
  std::vector<MarkerCandidate> candidates;  // every image candidate
  std::vector<FusionStatus> statuses;       // one per candidate
};

// The whole detector: image candidates, then laser confirmation and measurement.
class RobotDetector {
 public:
  static std::unique_ptr<RobotDetector> Create(const CameraModel& camera,
                                               const MarkerGeometry& geometry,
                                               const ColourModel& colours,
                                               const RobotDetectorOptions& options,
                                               std::string* error);

  // `scan` should be the scan closest in time to the image; detections carry its timestamp.
  // False with a message for an unusable image; an unusable scan only rejects candidates.
  bool Detect(const BgrImageView& image, const LaserScan& scan, const std::string& observer_id,
              FrameDetections* result, std::string* error) const;

  const MarkerDetector& marker_detector() const { return *marker_detector_; }

 private:
  RobotDetector(std::unique_ptr<MarkerDetector> marker_detector, const MarkerGeometry& geometry,
                const LaserFusionOptions& laser_options);

  const std::unique_ptr<MarkerDetector> marker_detector_;
  const MarkerGeometry geometry_;
  const LaserFusionOptions laser_options_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_ROBOT_DETECTOR_H_
