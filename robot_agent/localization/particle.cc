#include "robot_agent/localization/particle.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace fleetmap {

double MaxPositionStd(const Eigen::Matrix3d& covariance) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(covariance.topLeftCorner<2, 2>());
  return std::sqrt(std::max(0.0, solver.eigenvalues().maxCoeff()));
}

PoseEstimate ComputeEstimate(const std::vector<Particle>& particles,
                             const ConvergenceOptions& options) {
  PoseEstimate estimate;
  estimate.particle_count = static_cast<int>(particles.size());
  double total = 0.0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  double sum_cos = 0.0, sum_sin = 0.0;
  for (const Particle& p : particles) {
    total += p.weight;
    mean += p.weight * p.robot_in_map.translation();
    sum_cos += p.weight * std::cos(p.robot_in_map.rotation());
    sum_sin += p.weight * std::sin(p.robot_in_map.rotation());
  }
  if (!(total > 0.0)) {
    estimate.covariance = Eigen::Matrix3d::Identity() * 1e6;
    return estimate;
  }
  mean /= total;
  const double heading = std::atan2(sum_sin, sum_cos);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Particle& p : particles) {
    Eigen::Vector3d d;
    d.head<2>() = p.robot_in_map.translation() - mean;
    d.z() = NormalizeAngle(p.robot_in_map.rotation() - heading);
    cov += (p.weight / total) * d * d.transpose();
  }
  // The angular variance around the circular mean underestimates a uniform heading (it is
  // bounded by pi^2/3); the circular variance -2 ln R is the honest spread.
  const double resultant = std::hypot(sum_cos, sum_sin) / total;
  const double circular_variance = -2.0 * std::log(std::max(resultant, 1e-12));
  cov(2, 2) = std::max(cov(2, 2), circular_variance);
  estimate.robot_in_map = Rigid2d(mean, heading);
  estimate.covariance = cov;
  estimate.converged = MaxPositionStd(cov) <= options.max_position_std &&
                       std::sqrt(cov(2, 2)) <= options.max_heading_std;
  return estimate;
}

}  // namespace fleetmap
