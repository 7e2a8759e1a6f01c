#ifndef FLEETMAP_SHARED_CORE_LIKELIHOOD_FIELD_H_
#define FLEETMAP_SHARED_CORE_LIKELIHOOD_FIELD_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"

namespace fleetmap {

struct LikelihoodFieldOptions {
  float occupied_probability = 0.6f;  // cells above it count as obstacles
  double max_distance = 1.0;          // metres; distances are clamped here
};

// Distance from every cell centre to the nearest obstacle cell centre (exact Euclidean distance
// transform), for scan matching and the likelihood-field sensor model. The field covers the grid
// plus a margin of `max_distance`, so points slightly outside the grid still read true distances.
class LikelihoodField {
 public:
  LikelihoodField(const OccupancyGrid& grid, const LikelihoodFieldOptions& options);
  // From obstacle points directly (useful for tests and for point-cloud maps).
  LikelihoodField(const std::vector<Eigen::Vector2d>& obstacles, double resolution,
                  const LikelihoodFieldOptions& options);

  double resolution() const { return resolution_; }
  double max_distance() const { return options_.max_distance; }
  const Eigen::Vector2d& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }
  bool has_obstacles() const { return has_obstacles_; }

  // Distance at a cell centre; max_distance outside the field.
  float CellDistance(int x, int y) const;
  // Bilinearly interpolated distance at a point (metres); max_distance outside the field.
  double Distance(const Eigen::Vector2d& point) const;
  // Distance and its gradient with respect to the point (zero gradient outside the field).
  double DistanceAndGradient(const Eigen::Vector2d& point, Eigen::Vector2d* gradient) const;

 private:
  void Compute(const std::vector<uint8_t>& obstacle_mask);

  LikelihoodFieldOptions options_;
  double resolution_ = 0.05;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // lower-left corner of cell (0, 0)
  int width_ = 0;
  int height_ = 0;
  bool has_obstacles_ = false;
  std::vector<float> distance_;  // metres, row-major
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_LIKELIHOOD_FIELD_H_
