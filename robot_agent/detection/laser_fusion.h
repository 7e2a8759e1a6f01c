#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_LASER_FUSION_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_LASER_FUSION_H_

#include <string>

#include "robot_agent/detection/camera_model.h"
#include "robot_agent/detection/detection.h"
#include "robot_agent/detection/marker_detector.h"
#include "shared/core/laser_scan.h"

namespace fleetmap {

struct LaserFusionOptions {
  double range_noise = 0.01;       // metres, sigma of the scanner's ranges
  double bearing_margin = 0.035;   // radians added either side of the image's bearing window
  double range_window = 0.35;      // relative uncertainty of the image's size-based range
  // Consecutive returns further apart than max(min_jump, jump_beams * beam spacing) belong to
  // different objects.
  double min_jump = 0.10;          // metres
  double jump_beams = 2.5;
  int min_returns = 2;
  double max_rms_sigmas = 3.5;     // fit RMS allowed, in units of range_noise
  double width_tolerance = 0.08;   // metres beyond the body's diameter
  // Largest difference between the laser's range and the marker-size range: metres plus a share
  // of the range.
  double range_tolerance = 0.15;
  double range_agreement = 0.2;
  // Allowed angle between the marker's bearing and the fitted body's, radians, plus a share of
  // the marker's angular width.
  double bearing_tolerance = 0.012;
  double covariance_floor = 0.001; // metres, sigma added for unmodelled effects
};

enum class FusionStatus {
  kConfirmed,
  kBadScan,               // empty scan or a scan whose numbers make no sense
  kNoReturnsNearBearing,  // nothing the laser saw lies where the camera saw the marker
  kSurfaceTooWide,        // flat or wide surface: a wall, e.g. a poster on it
  kNoDepthEdge,           // the object does not stand out in front of its surroundings
  kTooFewReturns,
  kPoorFit,               // not a circle of the body's radius
  kRangeMismatch,         // laser range disagrees with the marker's apparent size
  kBearingMismatch,       // the body found is beside the marker, not under it
};

const char* FusionStatusName(FusionStatus status);

struct FusionResult {
  FusionStatus status = FusionStatus::kBadScan;
  RobotDetection detection;  // filled when status == kConfirmed (ids and time left to caller)
};

// Confirms an image candidate with the laser scan taken at the same time and measures the
// seen robot's centre by fitting a circle of the body's radius to the returns around the
// candidate's bearing.
FusionResult FuseWithLaser(const MarkerCandidate& candidate, const LaserScan& scan,
                           const CameraModel& camera, const MarkerGeometry& geometry,
                           const LaserFusionOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_LASER_FUSION_H_
