#ifndef FLEETMAP_MAP_SERVER_MERGE_SIDED_DISTANCE_FIELD_H_
#define FLEETMAP_MAP_SERVER_MERGE_SIDED_DISTANCE_FIELD_H_

#include <Eigen/Core>
#include <array>
#include <memory>

#include "map_server/merge/log_odds_canvas.h"
#include "shared/core/likelihood_field.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// Distances from a point to a target map's walls, counting only walls seen from the point's side.
//
// Two robots that drive a corridor in opposite directions see the two faces of every door jamb
// and room divider, a wall thickness apart; matched by plain distance, each face snaps onto the
// other one and the maps slide along the corridor by the wall thickness (15-20 cm measured in
// the department, where both maps sat within 2.5 cm of the true walls). Here a source wall point
// with a normal (the side its map saw it from, see WallNormals) only finds target walls whose
// normal is within kMaxAngle of it; a point without one (seen from both sides) finds any wall.
class SidedDistanceField {
 public:
  static constexpr int kSectors = 8;
  static constexpr double kMaxAngle = 67.5 * 3.14159265358979323846 / 180.0;

  // Walls are the target's cells above `occupied_log_odds` inside `box` (farther points find
  // none); sides come from the cells below `free_log_odds`. `unsided` is the plain distance
  // field of the same walls.
  SidedDistanceField(const OccupancyGrid& target, const Box2d& box, float occupied_log_odds,
                     float free_log_odds, std::shared_ptr<const LikelihoodField> unsided);

  double max_distance() const { return unsided_->max_distance(); }
  double resolution() const { return unsided_->resolution(); }
  // The sector a source wall with this side (target frame; zero for none) looks in: -1 for all.
  static int SectorOf(const Eigen::Vector2d& normal);
  // Distance (metres, at most max_distance()) to the walls of `sector` and its gradient with
  // respect to `point`.
  double DistanceAndGradient(const Eigen::Vector2d& point, int sector,
                             Eigen::Vector2d* gradient) const {
    const LikelihoodField& field = sector < 0 ? *unsided_ : *sectors_[static_cast<size_t>(sector)];
    return field.DistanceAndGradient(point, gradient);
  }

 private:
  // Sector k holds the walls whose normal lies within kMaxAngle of direction k * 45 degrees,
  // and the walls without one.
  std::array<std::unique_ptr<LikelihoodField>, kSectors> sectors_;
  std::shared_ptr<const LikelihoodField> unsided_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_SIDED_DISTANCE_FIELD_H_
