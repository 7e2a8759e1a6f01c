#include "robot_agent/slam/particle_scan_matcher.h"

#include <cmath>

namespace fleetmap {

ParticleMatch MatchAgainstTiles(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                                const Rigid2d& initial, const ParticleMatcherOptions& options) {
  ParticleMatch result;
  result.pose = initial;
  if (static_cast<int>(points.size()) < options.min_points) return result;
  Rigid2d pose = initial;
  int matched = 0;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const int radius = iteration < options.coarse_iterations ? options.coarse_radius : options.fine_radius;
    // Closed-form rigid alignment (2D Procrustes) of the transformed points to their
    // correspondences.
    Eigen::Vector2d mean_p = Eigen::Vector2d::Zero(), mean_q = Eigen::Vector2d::Zero();
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> pairs;
    pairs.reserve(points.size());
    for (const Eigen::Vector2f& p : points) {
      const Eigen::Vector2d in_map = pose * Eigen::Vector2d(p.cast<double>());
      Eigen::Vector2d hit;
      double d2;
      if (!grid.NearestHit(in_map, radius, &hit, &d2)) continue;
      pairs.emplace_back(in_map, hit);
      mean_p += in_map;
      mean_q += hit;
    }
    matched = static_cast<int>(pairs.size());
    if (matched < options.min_points) break;
    mean_p /= matched;
    mean_q /= matched;
    double sxx = 0.0, sxy = 0.0;
    for (const auto& [p, q] : pairs) {
      const Eigen::Vector2d a = p - mean_p, b = q - mean_q;
      sxx += a.x() * b.x() + a.y() * b.y();
      sxy += a.x() * b.y() - a.y() * b.x();
    }
    const double angle = std::atan2(sxy, sxx);
    const double c = std::cos(angle), s = std::sin(angle);
    Eigen::Matrix2d rotation;
    rotation << c, -s, s, c;
    const Eigen::Vector2d translation = mean_q - rotation * mean_p;
    const Rigid2d step(translation, angle);
    pose = step * pose;
    if (iteration >= options.coarse_iterations && translation.norm() < options.min_step &&
        std::abs(angle) < options.min_step) {
      break;
    }
  }
  result.pose = pose;
  result.inlier_fraction = InlierFraction(points, grid, pose, options);
  result.good = matched >= options.min_points && result.inlier_fraction >= options.min_inlier_fraction;
  return result;
}

double InlierFraction(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                      const Rigid2d& pose, const ParticleMatcherOptions& options) {
  if (points.empty()) return 0.0;
  int inliers = 0;
  for (const Eigen::Vector2f& p : points) {
    Eigen::Vector2d hit;
    double d2;
    if (grid.NearestHit(pose * Eigen::Vector2d(p.cast<double>()), options.fine_radius, &hit, &d2)) ++inliers;
  }
  return static_cast<double>(inliers) / static_cast<double>(points.size());
}

bool GoodMatchAt(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                 const Rigid2d& pose, const ParticleMatcherOptions& options) {
  return static_cast<int>(points.size()) >= options.min_points &&
         InlierFraction(points, grid, pose, options) >= options.min_inlier_fraction;
}

double ScanLogLikelihood(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                         const Rigid2d& pose, const ParticleMatcherOptions& options) {
  const double limit = options.fine_radius * grid.resolution();
  const double limit2 = limit * limit;
  const double scale = -0.5 / (options.sigma * options.sigma);
  double sum = 0.0;
  for (const Eigen::Vector2f& p : points) {
    Eigen::Vector2d hit;
    double d2;
    if (!grid.NearestHit(pose * Eigen::Vector2d(p.cast<double>()), options.fine_radius, &hit, &d2) || d2 > limit2) {
      d2 = limit2;
    }
    sum += scale * d2;
  }
  return sum;
}

}  // namespace fleetmap
