#include "shared/eval/rigid_alignment.h"

#include <cmath>

namespace fleetmap {

std::optional<Rigid2d> AlignPoints2d(const std::vector<Eigen::Vector2d>& source,
                                     const std::vector<Eigen::Vector2d>& target) {
  if (source.size() != target.size() || source.size() < 2) return std::nullopt;
  const double n = static_cast<double>(source.size());
  Eigen::Vector2d source_mean = Eigen::Vector2d::Zero();
  Eigen::Vector2d target_mean = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < source.size(); ++i) {
    source_mean += source[i];
    target_mean += target[i];
  }
  source_mean /= n;
  target_mean /= n;
  // In 2D the optimal rotation angle is atan2 of the summed cross and dot products of the
  // centred point pairs (the SVD of the 2x2 covariance reduces to this).
  double dot = 0.0;
  double cross = 0.0;
  double spread = 0.0;
  for (size_t i = 0; i < source.size(); ++i) {
    const Eigen::Vector2d a = source[i] - source_mean;
    const Eigen::Vector2d b = target[i] - target_mean;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
    spread += a.squaredNorm();
  }
  if (spread < 1e-12) return std::nullopt;
  const double angle = std::atan2(cross, dot);
  const Rigid2d rotation(Eigen::Vector2d::Zero(), angle);
  return Rigid2d(target_mean - rotation * source_mean, angle);
}

}  // namespace fleetmap
