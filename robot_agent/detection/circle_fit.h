#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_CIRCLE_FIT_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_CIRCLE_FIT_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace fleetmap {

// One laser return: unit beam direction and measured range, in the sensor frame.
struct BeamReturn {
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
  double range = 0.0;
  Eigen::Vector2d point() const { return range * direction; }
};

struct CircleFit {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  // J^T J of the range residuals at the solution; the centre's covariance is
  // sigma^2 * information^-1 for range noise sigma.
  Eigen::Matrix2d information = Eigen::Matrix2d::Zero();
  double rms = 0.0;  // metres, range residuals
  int iterations = 0;
};

// Fits a circle of known radius to the returns of the beams that hit it, by Gauss-Newton on
// the range residuals: each beam's predicted range is where its ray first meets the circle, so
// noise is modelled along the beam as the scanner makes it (beams that the current estimate
// misses fall back to the point-to-circle distance). Needs at least two returns; returns
// nullopt when the problem is degenerate or the fit ends with the centre in front of the
// returns (a concave fit).
std::optional<CircleFit> FitCircleKnownRadius(const std::vector<BeamReturn>& beams,
                                              double radius, int max_iterations = 20);

// RMS distance of the returns' end points to their best-fitting line (total least squares).
double LineFitRms(const std::vector<BeamReturn>& beams);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_CIRCLE_FIT_H_
