#include "robot_agent/detection/laser_fusion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "robot_agent/detection/circle_fit.h"

namespace fleetmap {
namespace {

struct Segment {
  int first = 0;  // beam indices, inclusive
  int last = 0;
};

// Splits the scan into runs of returns that belong to one object.
std::vector<Segment> SegmentScan(const LaserScan& scan, const LaserFusionOptions& options) {
  std::vector<Segment> segments;
  int start = -1;
  Eigen::Vector2d previous = Eigen::Vector2d::Zero();
  for (int i = 0; i < scan.size(); ++i) {
    if (!scan.IsReturn(i)) {
      if (start >= 0) segments.push_back({start, i - 1});
      start = -1;
      continue;
    }
    const double range = scan.ranges[i];
    const Eigen::Vector2d point(range * std::cos(scan.angle(i)), range * std::sin(scan.angle(i)));
    const double jump =
        std::max(options.min_jump, options.jump_beams * range * std::abs(scan.angle_increment));
    if (start >= 0 && (point - previous).norm() > jump) {
      segments.push_back({start, i - 1});
      start = -1;
    }
    if (start < 0) start = i;
    previous = point;
  }
  if (start >= 0) segments.push_back({start, scan.size() - 1});
  return segments;
}

double AngleOf(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

BeamReturn BeamAt(const LaserScan& scan, int i) {
  const double a = scan.angle(i);
  return BeamReturn{Eigen::Vector2d(std::cos(a), std::sin(a)), scan.ranges[i]};
}

// The segment where the candidate's body should be: among the objects inside the bearing window
// the camera allows, the one whose range best matches the marker's apparent size.
std::optional<Segment> FindBodySegment(const MarkerCandidate& candidate, const LaserScan& scan,
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

  std::optional<Segment> best;
  double best_error = 0.0;
  for (const Segment& segment : SegmentScan(scan, options)) {
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

// Checks that `segment` is a free-standing body of the known radius and fits it: narrow, in
// front of its surroundings (or hidden on one side by something nearer), round rather than flat.
FusionStatus MeasureBody(const LaserScan& scan, Segment segment, const MarkerGeometry& geometry,
                         const LaserFusionOptions& options, CircleFit* fit, int* returns) {
  std::vector<BeamReturn> beams;
  auto collect = [&]() {
    beams.clear();
    for (int i = segment.first; i <= segment.last; ++i) beams.push_back(BeamAt(scan, i));
  };
  // A robot is narrower than its diameter; a wall (and a poster on it) is not.
  auto too_wide = [&]() {
    double nearest = std::numeric_limits<double>::infinity();
    for (const BeamReturn& beam : beams) nearest = std::min(nearest, beam.range);
    const double width = (beams.front().point() - beams.back().point()).norm();
    return width > 2.0 * geometry.body_radius + options.width_tolerance +
                       nearest * std::abs(scan.angle_increment);
  };
  collect();
  if (too_wide()) return FusionStatus::kSurfaceTooWide;
  if (static_cast<int>(beams.size()) < std::max(2, options.min_returns)) {
    return FusionStatus::kTooFewReturns;
  }
  std::optional<CircleFit> circle = FitCircleKnownRadius(beams, geometry.body_radius);
  if (!circle) return FusionStatus::kPoorFit;
  // Steep returns near the body's limbs can be split off by the segmentation; take back the
  // neighbours that lie on the fitted circle, then refit.
  const double on_circle = std::max(3.0 * options.range_noise, 0.02);
  auto lies_on_circle = [&](int i) {
    if (i < 0 || i >= scan.size() || !scan.IsReturn(i)) return false;
    return std::abs((BeamAt(scan, i).point() - circle->center).norm() - geometry.body_radius) <
           on_circle;
  };
  const Segment before = segment;
  while (lies_on_circle(segment.first - 1)) --segment.first;
  while (lies_on_circle(segment.last + 1)) ++segment.last;
  if (segment.first != before.first || segment.last != before.last) {
    collect();
    if (too_wide()) return FusionStatus::kSurfaceTooWide;
    circle = FitCircleKnownRadius(beams, geometry.body_radius);
    if (!circle) return FusionStatus::kPoorFit;
  }
  // It must stand in front of what is beside it (no return counts as far away). A nearer
  // neighbour on one side is an occluder (another robot's body may hide part of this one from
  // the laser while its marker, higher up, stays in view); then the visible arc must show its
  // curvature on its own.
  double nearest = std::numeric_limits<double>::infinity();
  for (const BeamReturn& beam : beams) nearest = std::min(nearest, beam.range);
  auto stands_out_at = [&](int i) {
    if (i < 0 || i >= scan.size() || !scan.IsReturn(i)) return true;
    return scan.ranges[i] > nearest + options.min_jump;
  };
  auto occluder_at = [&](int i, int end) {
    return i >= 0 && i < scan.size() && scan.IsReturn(i) &&
           scan.ranges[i] < scan.ranges[end] - options.min_jump;
  };
  const bool left_out = stands_out_at(segment.first - 1);
  const bool right_out = stands_out_at(segment.last + 1);
  const bool occluded = (left_out && occluder_at(segment.last + 1, segment.last)) ||
                        (right_out && occluder_at(segment.first - 1, segment.first));
  if (!(left_out && right_out) && !(occluded && beams.size() >= 3)) {
    return FusionStatus::kNoDepthEdge;
  }
  if (circle->rms > options.max_rms_sigmas * options.range_noise ||
      (beams.size() >= (occluded ? 3u : 4u) && LineFitRms(beams) < circle->rms)) {
    return FusionStatus::kPoorFit;
  }
  *fit = *circle;
  *returns = static_cast<int>(beams.size());
  return FusionStatus::kConfirmed;
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
  const std::optional<Segment> segment =
      FindBodySegment(candidate, scan, camera, geometry, options);
  if (!segment) {
    result.status = FusionStatus::kNoReturnsNearBearing;
    return result;
  }
  CircleFit fit;
  int returns = 0;
  result.status = MeasureBody(scan, *segment, geometry, options, &fit, &returns);
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
