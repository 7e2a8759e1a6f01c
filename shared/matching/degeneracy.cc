#include "shared/matching/degeneracy.h"

#include <Eigen/Eigenvalues>

namespace fleetmap {

Eigen::Matrix2d NormalScatter(const std::vector<Eigen::Vector2f>& points, double max_gap) {
  // Tangents span at least kSpan either side (range noise would tilt shorter ones), walking
  // along the beams without crossing a gap.
  constexpr float kSpan = 0.1f;
  constexpr int kMaxSteps = 10;
  const float max_gap_f = static_cast<float>(max_gap);
  const int n = static_cast<int>(points.size());
  auto walk = [&](int i, int step) {
    int j = i;
    for (int k = 0; k < kMaxSteps; ++k) {
      const int next = j + step;
      if (next < 0 || next >= n) return -1;
      if ((points[static_cast<size_t>(next)] - points[static_cast<size_t>(j)]).norm() > max_gap_f)
        return -1;
      j = next;
      if ((points[static_cast<size_t>(j)] - points[static_cast<size_t>(i)]).norm() >= kSpan)
        return j;
    }
    return -1;
  };
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const int back = walk(i, -1), forward = walk(i, 1);
    if (back < 0 || forward < 0) continue;
    const Eigen::Vector2f tangent =
        points[static_cast<size_t>(forward)] - points[static_cast<size_t>(back)];
    const float length = tangent.norm();
    if (length < 1e-6f) continue;
    const Eigen::Vector2d normal(-tangent.y() / length, tangent.x() / length);
    scatter += normal * normal.transpose();
    ++count;
  }
  return count > 0 ? Eigen::Matrix2d(scatter / count) : Eigen::Matrix2d::Zero();
}

Rigid2d KeepObservedDirections(const Rigid2d& predicted, const Rigid2d& matched,
                               const Eigen::Matrix2d& scatter_in_robot, double min_eigenvalue) {
  const Eigen::Matrix2d rotation = matched.rotation_matrix();
  const Eigen::Matrix2d scatter = rotation * scatter_in_robot * rotation.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  const Eigen::Vector2d change = matched.translation() - predicted.translation();
  Eigen::Vector2d kept = Eigen::Vector2d::Zero();
  for (int i = 0; i < 2; ++i) {
    if (solver.eigenvalues()(i) < min_eigenvalue) continue;
    const Eigen::Vector2d direction = solver.eigenvectors().col(i);
    kept += direction * direction.dot(change);
  }
  return Rigid2d(predicted.translation() + kept, matched.rotation());
}

}  // namespace fleetmap
