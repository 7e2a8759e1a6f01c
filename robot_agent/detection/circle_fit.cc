#include "robot_agent/detection/circle_fit.h"

#include <cmath>

#include <Eigen/Dense>

namespace fleetmap {
namespace {

// Residual (measured - predicted range) and its Jacobian with respect to the centre.
void Linearize(const BeamReturn& beam, const Eigen::Vector2d& center, double radius,
               double* residual, Eigen::Vector2d* jacobian) {
  const Eigen::Vector2d& u = beam.direction;
  const double along = u.dot(center);
  const double q = radius * radius - center.squaredNorm() + along * along;
  if (along > 0.0 && q > 0.0025 * radius * radius) {
    const double root = std::sqrt(q);
    *residual = beam.range - (along - root);
    *jacobian = -(u - (along * u - center) / root);
    return;
  }
  // The ray misses (or grazes) the current circle: pull the end point onto it instead.
  const Eigen::Vector2d offset = beam.point() - center;
  const double distance = std::max(offset.norm(), 1e-9);
  *residual = distance - radius;
  *jacobian = -offset / distance;
}

}  // namespace

std::optional<CircleFit> FitCircleKnownRadius(const std::vector<BeamReturn>& beams,
                                              double radius, int max_iterations) {
  if (beams.size() < 2 || !(radius > 0.0)) return std::nullopt;
  // Start behind the return nearest the sensor, one radius further along its beam.
  const BeamReturn* nearest = &beams.front();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const BeamReturn& beam : beams) {
    if (!std::isfinite(beam.range) || !(beam.range > 0.0)) return std::nullopt;
    if (beam.range < nearest->range) nearest = &beam;
    mean += beam.point();
  }
  mean /= static_cast<double>(beams.size());
  CircleFit fit;
  fit.center = nearest->point() + radius * mean.normalized();
  for (fit.iterations = 1; fit.iterations <= max_iterations; ++fit.iterations) {
    Eigen::Matrix2d jtj = Eigen::Matrix2d::Zero();
    Eigen::Vector2d jtr = Eigen::Vector2d::Zero();
    for (const BeamReturn& beam : beams) {
      double r;
      Eigen::Vector2d j;
      Linearize(beam, fit.center, radius, &r, &j);
      jtj += j * j.transpose();
      jtr += j * r;
    }
    // A touch of damping keeps two-return fits (exactly determined) well posed.
    const Eigen::Matrix2d damped = jtj + 1e-9 * Eigen::Matrix2d::Identity();
    const Eigen::Vector2d step = -damped.ldlt().solve(jtr);
    if (!step.allFinite()) return std::nullopt;
    // Limit the step so one bad linearisation cannot throw the centre across the room.
    const double max_step = 0.5 * radius;
    fit.center += step.norm() > max_step ? (max_step / step.norm()) * step : step;
    if (step.norm() < 1e-7) break;
  }
  double sum_squares = 0.0;
  fit.information.setZero();
  for (const BeamReturn& beam : beams) {
    double r;
    Eigen::Vector2d j;
    Linearize(beam, fit.center, radius, &r, &j);
    sum_squares += r * r;
    fit.information += j * j.transpose();
  }
  fit.rms = std::sqrt(sum_squares / static_cast<double>(beams.size()));
  // The surface seen must face the sensor: the centre lies beyond the mean return.
  if (fit.center.norm() <= mean.norm()) return std::nullopt;
  if (std::abs(fit.information.determinant()) < 1e-12) return std::nullopt;
  return fit;
}

double LineFitRms(const std::vector<BeamReturn>& beams) {
  if (beams.size() < 3) return 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const BeamReturn& beam : beams) mean += beam.point();
  mean /= static_cast<double>(beams.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const BeamReturn& beam : beams) {
    const Eigen::Vector2d d = beam.point() - mean;
    scatter += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  return std::sqrt(std::max(0.0, solver.eigenvalues()(0)) / static_cast<double>(beams.size()));
}

}  // namespace fleetmap
