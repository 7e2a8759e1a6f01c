#include "robot_agent/slam/local_match_map.h"

#include <algorithm>

namespace fleetmap {

LocalMatchMap::LocalMatchMap(const LocalMatchMapOptions& options) : options_(options) {
  options_.scans_per_grid = std::max(1, options_.scans_per_grid);
  grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
}

void LocalMatchMap::Insert(const std::vector<Eigen::Vector2f>& points_in_robot,
                           const Rigid2d& robot_in_local) {
  if (grids_.back().scans >= options_.scans_per_grid) {
    grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
  }
  for (Entry& entry : grids_) {
    entry.grid->AddPoints(points_in_robot, robot_in_local);
    ++entry.scans;
  }
  if (grids_.size() > 1 && grids_.front().scans >= 2 * options_.scans_per_grid) {
    grids_.erase(grids_.begin());
  }
  ++inserted_;
}

}  // namespace fleetmap
