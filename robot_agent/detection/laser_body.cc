#include "robot_agent/detection/laser_body.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace fleetmap {

std::vector<BeamRun> SplitIntoRuns(const LaserScan& scan, const LaserFusionOptions& options) {
  std::vector<BeamRun> segments;
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

BeamReturn BeamAt(const LaserScan& scan, int i) {
  const double a = scan.angle(i);
  return BeamReturn{Eigen::Vector2d(std::cos(a), std::sin(a)), scan.ranges[i]};
}

FusionStatus MeasureBody(const LaserScan& scan, BeamRun* measured, double body_radius,
                         const LaserFusionOptions& options, CircleFit* fit, int* returns) {
  BeamRun& segment = *measured;
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
    return width > 2.0 * body_radius + options.width_tolerance +
                       nearest * std::abs(scan.angle_increment);
  };
  collect();
  if (too_wide()) return FusionStatus::kSurfaceTooWide;
  if (static_cast<int>(beams.size()) < std::max(2, options.min_returns)) {
    return FusionStatus::kTooFewReturns;
  }
  std::optional<CircleFit> circle = FitCircleKnownRadius(beams, body_radius);
  if (!circle) return FusionStatus::kPoorFit;
  // Steep returns near the body's limbs can be split off by the segmentation; take back the
  // neighbours that lie on the fitted circle, then refit.
  const double on_circle = std::max(3.0 * options.range_noise, 0.02);
  auto lies_on_circle = [&](int i) {
    if (i < 0 || i >= scan.size() || !scan.IsReturn(i)) return false;
    return std::abs((BeamAt(scan, i).point() - circle->center).norm() - body_radius) <
           on_circle;
  };
  const BeamRun before = segment;
  while (lies_on_circle(segment.first - 1)) --segment.first;
  while (lies_on_circle(segment.last + 1)) ++segment.last;
  if (segment.first != before.first || segment.last != before.last) {
    collect();
    if (too_wide()) return FusionStatus::kSurfaceTooWide;
    circle = FitCircleKnownRadius(beams, body_radius);
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

std::vector<Eigen::Vector2d> FindLaserBodies(const LaserScan& scan, double body_radius,
                                             const LaserBodyOptions& options) {
  std::vector<Eigen::Vector2d> bodies;
  if (scan.size() == 0 || !(body_radius > 0.0) || !std::isfinite(scan.angle_increment) ||
      scan.angle_increment == 0.0f || !scan.sensor_in_robot.IsFinite()) {
    return bodies;
  }
  for (const BeamRun& segment : SplitIntoRuns(scan, options.fusion)) {
    CircleFit fit;
    int returns = 0;
    BeamRun body = segment;
    if (MeasureBody(scan, &body, body_radius, options.fusion, &fit, &returns) !=
            FusionStatus::kConfirmed ||
        returns < options.min_returns ||
        fit.rms > options.max_rms_sigmas * options.fusion.range_noise) {
      continue;
    }
    std::vector<BeamReturn> beams;
    for (int i = body.first; i <= body.last; ++i) beams.push_back(BeamAt(scan, i));
    if (LineFitRms(beams) < std::max(options.min_line_rms_sigmas * options.fusion.range_noise,
                                     2.0 * fit.rms)) {
      continue;
    }
    bodies.push_back(scan.sensor_in_robot * fit.center);
  }
  return bodies;
}

}  // namespace fleetmap
