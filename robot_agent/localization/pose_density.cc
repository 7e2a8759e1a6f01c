#include "robot_agent/localization/pose_density.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "robot_agent/localization/particle_clusters.h"
#include "robot_agent/localization/resampling.h"

namespace fleetmap {
namespace {

bool IsPositiveDefinite(const Eigen::Matrix2d& m) {
  return m.allFinite() && m(0, 0) > 0.0 && m.determinant() > 0.0;
}

}  // namespace

double PoseDensity::Evaluate(const Rigid2d& robot_in_map) const {
  double density = 0.0;
  for (const PoseDensityKernel& k : kernels) {
    const Eigen::Vector2d d = robot_in_map.translation() - k.mean;
    const double det = k.covariance.determinant();
    if (!(det > 0.0)) continue;
    const double mahalanobis = d.dot(k.covariance.inverse() * d);
    if (mahalanobis > 50.0) continue;  // exp(-25): negligible, skip the rest of the work
    double value = std::exp(-0.5 * mahalanobis) / (2.0 * M_PI * std::sqrt(det));
    if (has_heading) {
      const double dt = NormalizeAngle(robot_in_map.rotation() - k.heading);
      const double var = std::max(k.heading_variance, 1e-8);
      value *= std::exp(-0.5 * dt * dt / var) / std::sqrt(2.0 * M_PI * var);
    } else {
      value /= 2.0 * M_PI;
    }
    density += k.weight * value;
  }
  return density;
}

Rigid2d PoseDensity::Sample(std::mt19937& rng) const {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  double pick = unit(rng);
  const PoseDensityKernel* chosen = &kernels.back();
  for (const PoseDensityKernel& k : kernels) {
    pick -= k.weight;
    if (pick <= 0.0) {
      chosen = &k;
      break;
    }
  }
  const Eigen::Matrix2d factor = Eigen::LLT<Eigen::Matrix2d>(chosen->covariance).matrixL();
  const Eigen::Vector2d position = chosen->mean + factor * Eigen::Vector2d(normal(rng), normal(rng));
  const double heading = has_heading
                             ? chosen->heading + std::sqrt(chosen->heading_variance) * normal(rng)
                             : M_PI * (2.0 * unit(rng) - 1.0);
  return Rigid2d(position, heading);
}

std::optional<PoseDensity> SummarizeDetection(const std::vector<Particle>& observer_particles,
                                              const RobotDetection& detection,
                                              const DetectionSummaryOptions& options,
                                              std::mt19937& rng) {
  if (observer_particles.empty() || !detection.position_in_observer.allFinite() ||
      !IsPositiveDefinite(detection.covariance)) {
    return std::nullopt;
  }
  const bool has_heading = detection.relative_heading.has_value() &&
                           std::isfinite(*detection.relative_heading) &&
                           std::isfinite(detection.relative_heading_variance) &&
                           detection.relative_heading_variance >= 0.0;
  ConvergenceOptions focus;
  focus.max_position_std = options.max_observer_position_std;
  focus.max_heading_std = options.max_observer_heading_std;
  if (!ComputeClusteredEstimate(observer_particles, focus).converged) return std::nullopt;

  std::vector<int> indices;
  LowVarianceSelect(observer_particles, std::max(1, options.max_kernels), rng, &indices);
  PoseDensity density;
  density.observer_id = detection.observer_id;
  density.observed_id = detection.observed_id;
  density.timestamp = detection.timestamp;
  density.has_heading = has_heading;
  // Kernel centres: each chosen observer pose composed with the detected position.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const int index : indices) {
    const Rigid2d& observer_in_map = observer_particles[static_cast<size_t>(index)].robot_in_map;
    PoseDensityKernel kernel;
    kernel.weight = 1.0 / static_cast<double>(indices.size());
    kernel.mean = observer_in_map * detection.position_in_observer;
    const Eigen::Matrix2d rotation = observer_in_map.rotation_matrix();
    kernel.covariance = rotation * detection.covariance * rotation.transpose();
    if (has_heading) {
      kernel.heading = NormalizeAngle(observer_in_map.rotation() + *detection.relative_heading);
      kernel.heading_variance = detection.relative_heading_variance;
    }
    mean += kernel.mean;
    density.kernels.push_back(kernel);
  }
  // Silverman-style bandwidth from the spread of the centres, so that K kernels stand in for the
  // observer's whole particle set.
  mean /= static_cast<double>(density.kernels.size());
  double spread = 0.0;
  for (const PoseDensityKernel& k : density.kernels) spread += (k.mean - mean).squaredNorm();
  spread = std::sqrt(spread / (2.0 * density.kernels.size()));
  const double silverman = spread * std::pow(static_cast<double>(density.kernels.size()), -1.0 / 6);
  const double h = std::hypot(silverman, options.min_bandwidth_xy);
  for (PoseDensityKernel& k : density.kernels) {
    k.covariance += h * h * Eigen::Matrix2d::Identity();
    k.heading_variance += options.min_bandwidth_theta * options.min_bandwidth_theta;
  }
  return density;
}

}  // namespace fleetmap
