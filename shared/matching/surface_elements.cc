#include "shared/matching/surface_elements.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <Eigen/Eigenvalues>

namespace fleetmap {
namespace {

// Buckets of `size` x `size` metres, so a point's neighbours are in its bucket and the 8 around.
class PointBuckets {
 public:
  PointBuckets(const std::vector<Eigen::Vector2d>& points, double size) : size_(size) {
    buckets_.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) buckets_[Key(Cell(points[i]))].push_back(static_cast<int>(i));
  }

  template <typename Visit>
  void ForEachNear(const Eigen::Vector2d& p, Visit visit) const {
    const Eigen::Array2i c = Cell(p);
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = buckets_.find(Key(c + Eigen::Array2i(dx, dy)));
        if (it == buckets_.end()) continue;
        for (int i : it->second) visit(i);
      }
    }
  }

 private:
  Eigen::Array2i Cell(const Eigen::Vector2d& p) const {
    return Eigen::Array2i(static_cast<int>(std::floor(p.x() / size_)),
                          static_cast<int>(std::floor(p.y() / size_)));
  }
  static int64_t Key(const Eigen::Array2i& c) {
    return (static_cast<int64_t>(c.x()) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(c.y()));
  }

  double size_;
  std::unordered_map<int64_t, std::vector<int>> buckets_;
};

// Bucket coordinates must fit an int; beyond that a point is left as a point.
constexpr double kMaxCoordinate = 1e6;

}  // namespace

std::vector<SurfaceElement> FitSurfaceElements(const std::vector<Eigen::Vector2d>& points,
                                               double min_extent, const SurfaceFitOptions& options) {
  std::vector<SurfaceElement> elements(points.size());
  for (size_t i = 0; i < points.size(); ++i) elements[i].centre = points[i];
  if (!(options.radius > 0.0) || points.size() < 2) return elements;

  std::vector<Eigen::Vector2d> bucketed;
  std::vector<int> original;  // bucketed index -> input index
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].cwiseAbs().maxCoeff() < kMaxCoordinate) {
      bucketed.push_back(points[i]);
      original.push_back(static_cast<int>(i));
    }
  }
  const PointBuckets buckets(bucketed, options.radius);
  const double radius2 = options.radius * options.radius;
  const double max_flatness2 = options.max_flatness * options.max_flatness;
  std::vector<int> near;
  for (size_t b = 0; b < bucketed.size(); ++b) {
    const Eigen::Vector2d& p = bucketed[b];
    near.clear();
    buckets.ForEachNear(p, [&](int j) {
      if ((bucketed[static_cast<size_t>(j)] - p).squaredNorm() <= radius2) near.push_back(j);
    });
    if (static_cast<int>(near.size()) < options.min_points) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (int j : near) mean += bucketed[static_cast<size_t>(j)];
    mean /= static_cast<double>(near.size());
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (int j : near) {
      const Eigen::Vector2d d = bucketed[static_cast<size_t>(j)] - mean;
      scatter += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter);
    const double across = std::max(0.0, eigen.eigenvalues()(0));
    const double along = eigen.eigenvalues()(1);
    if (!(along > 0.0) || across > max_flatness2 * along) continue;
    const Eigen::Vector2d tangent = eigen.eigenvectors().col(1).normalized();

    // How far the neighbours reach along the wall on each side, and the nearest gap on each.
    double farthest_minus = 0.0, farthest_plus = 0.0;
    double nearest_minus = INFINITY, nearest_plus = INFINITY;
    for (int j : near) {
      const double s = tangent.dot(bucketed[static_cast<size_t>(j)] - p);
      if (s > 0.0) {
        farthest_plus = std::max(farthest_plus, s);
        nearest_plus = std::min(nearest_plus, s);
      } else if (s < 0.0) {
        farthest_minus = std::max(farthest_minus, -s);
        nearest_minus = std::min(nearest_minus, -s);
      }
    }
    // Reach min_extent towards a close neighbour (it may not be kept by the map), halfway to a far
    // one, never beyond the farthest neighbour otherwise, and never past max_extent.
    auto extent = [&](double farthest, double nearest) {
      if (farthest <= 0.0) return 0.0;
      return std::min(options.max_extent, std::max(0.5 * nearest, std::min(min_extent, farthest)));
    };
    SurfaceElement& element = elements[static_cast<size_t>(original[b])];
    element.centre = mean + tangent * tangent.dot(p - mean);  // onto the fitted wall
    element.tangent = tangent;
    element.extent_minus = extent(farthest_minus, nearest_minus);
    element.extent_plus = extent(farthest_plus, nearest_plus);
  }
  return elements;
}

}  // namespace fleetmap
