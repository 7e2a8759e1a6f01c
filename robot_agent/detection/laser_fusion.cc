#include "robot_agent/detection/laser_fusion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "robot_agent/detection/laser_body.h"

namespace fleetmap {
namespace {

double AngleOf(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// The segment where the candidate's body should be: among the objects inside the bearing window
// the camera allows, the one whose range best matches the marker's apparent size.
std::optional<BeamRun> FindBodySegment(const MarkerCandidate& candidate, const LaserScan& scan,
                                       const CameraModel& camera, const MarkerGeometry& geometry,
                                       const LaserFusionOptions& options) {
  // The camera ray, sampled at the near and far ends of the size-based range, seen from the
  // laser: this bounds where the body can be despite the camera-laser parallax.
  const Rigid2d robot_to_sensor = scan.sensor_in_robot.inverse();
  const Eigen::Vector2d ray(std::cos(candidate.bearing_in_camera),
                            std::sin(candidate.bearing_in_camera));
  auto ray_point = [&](double range) -> Eigen::Vector2d {
    const Eigen::Vector2d in_camera = range * ray;
    return robot_to_sensor * (camera.camera_in_robot * in_camera);
  };
  const double range = candidate.range_from_size;
  const Eigen::Vector2d near_point = ray_point(std::max(0.05, range * (1.0 - options.range_window)));
  const Eigen::Vector2d far_point = ray_point(range * (1.0 + options.range_window));
  const Eigen::Vector2d size_point = ray_point(range);
  const double center_bearing = AngleOf(size_point);
  const double half_body = std::asin(std::min(1.0, geometry.body_radius / near_point.norm()));
  const double spread = std::max(std::abs(NormalizeAngle(AngleOf(near_point) - center_bearing)),
                                 std::abs(NormalizeAngle(AngleOf(far_point) - center_bearing)));
  const double half_window = spread + half_body + options.bearing_margin;
  const double expected_range = size_point.norm() - geometry.body_radius;

  std::optional<BeamRun> best;
  double best_error = 0.0;
  for (const BeamRun& segment : SplitIntoRuns(scan, options)) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = segment.first; i <= segment.last; ++i) {
      if (std::abs(NormalizeAngle(scan.angle(i) - center_bearing)) <= half_window) {
        nearest = std::min(nearest, static_cast<double>(scan.ranges[i]));
      }
    }
    if (!std::isfinite(nearest)) continue;
    const double error = std::abs(nearest - expected_range);
    if (!best || error < best_error) {
      best = segment;
      best_error = error;
    }
  }
  return best;
}

}  // namespace

const char* FusionStatusName(FusionStatus status) {
  switch (status) {
    case FusionStatus::kConfirmed: return "confirmed";
    case FusionStatus::kBadScan: return "bad scan";
    case FusionStatus::kNoReturnsNearBearing: return "no laser returns near the bearing";
    case FusionStatus::kSurfaceTooWide: return "laser surface too wide (wall)";
    case FusionStatus::kNoDepthEdge: return "no depth edge around the object";
    case FusionStatus::kTooFewReturns: return "too few laser returns";
    case FusionStatus::kPoorFit: return "laser returns do not fit the body circle";
    case FusionStatus::kRangeMismatch: return "laser range disagrees with apparent size";
    case FusionStatus::kBearingMismatch: return "laser body off the marker's bearing";
  }
  return "unknown";
}

FusionResult FuseWithLaser(const MarkerCandidate& candidate, const LaserScan& scan,
                           const CameraModel& camera, const MarkerGeometry& geometry,
                           const LaserFusionOptions& options) {
  FusionResult result;
  if (scan.size() == 0 || !(scan.angle_increment != 0.0f) || !std::isfinite(scan.angle_min) ||
      !std::isfinite(scan.angle_increment) || !scan.sensor_in_robot.IsFinite() ||
      !(candidate.range_from_size > 0.0) || !std::isfinite(candidate.bearing_in_camera)) {
    result.status = FusionStatus::kBadScan;
    return result;
  }
  const std::optional<BeamRun> segment =
      FindBodySegment(candidate, scan, camera, geometry, options);
  if (!segment) {
    result.status = FusionStatus::kNoReturnsNearBearing;
    return result;
  }
  CircleFit fit;
  int returns = 0;
  BeamRun body = *segment;
  result.status = MeasureBody(scan, &body, geometry.body_radius, options, &fit, &returns);
  if (result.status != FusionStatus::kConfirmed) return result;

  const Eigen::Vector2d center_in_robot = scan.sensor_in_robot * fit.center;
  const double image_range = candidate.position_in_robot.norm();
  if (std::abs(center_in_robot.norm() - image_range) >
      options.range_tolerance + options.range_agreement * image_range) {
    result.status = FusionStatus::kRangeMismatch;
    return result;
  }
  // The marker sits on the body's axis: the body must be where the camera saw the marker, not
  // merely near it (a poster beside a robot of another colour).
  const Eigen::Vector2d center_in_camera = camera.camera_in_robot.inverse() * center_in_robot;
  const double bearing_tolerance =
      options.bearing_tolerance + (candidate.truncated ? 0.5 : 0.25) * candidate.angular_width;
  if (std::abs(NormalizeAngle(AngleOf(center_in_camera) - candidate.bearing_in_camera)) >
      bearing_tolerance) {
    result.status = FusionStatus::kBearingMismatch;
    return result;
  }

  // Centre covariance from the fit; trust the nominal noise unless the residuals say worse.
  const double n = static_cast<double>(returns);
  const double residual_sigma = n > 2.0 ? fit.rms * std::sqrt(n / (n - 2.0)) : 0.0;
  const double sigma =
      residual_sigma > 2.0 * options.range_noise ? residual_sigma : options.range_noise;
  const Eigen::Matrix2d rotation = scan.sensor_in_robot.rotation_matrix();
  RobotDetection& detection = result.detection;
  detection.observed_id = candidate.robot_id;
  detection.position_in_observer = center_in_robot;
  detection.covariance = rotation * (sigma * sigma * fit.information.inverse()) *
                             rotation.transpose() +
                         options.covariance_floor * options.covariance_floor *
                             Eigen::Matrix2d::Identity();
  detection.laser_returns = returns;
  detection.fit_rms = fit.rms;
  detection.confidence = candidate.confidence;
  return result;
}

}  // namespace fleetmap
