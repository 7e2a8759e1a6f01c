#include "robot_agent/slam/local_match_map.h"

#include <algorithm>

namespace fleetmap {

MatchGridOptions LocalMatchMapOptions::DefaultGrid() {
  MatchGridOptions options;
  options.track_observed = true;
  // Seen space is only for recognising moved objects: searches keep scoring unseen cells 0.
  options.unknown_score = 0.0f;
  return options;
}

LocalMatchMap::LocalMatchMap(const LocalMatchMapOptions& options) : options_(options) {
  options_.scans_per_grid = std::max(1, options_.scans_per_grid);
  grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
}

void LocalMatchMap::Insert(const std::vector<Eigen::Vector2f>& points_in_robot,
                           const std::vector<Eigen::Vector2f>& free_ends_in_robot,
                           const Rigid2d& robot_in_local) {
  if (grids_.back().scans >= options_.scans_per_grid) {
    grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
  }
  // Decided once, against the fullest grid, so that a grid started a moment ago (which has seen
  // nothing yet) does not map the moving object either.
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points_in_robot.size());
  const MatchGrid& fullest = *grids_.front().grid;
  for (const Eigen::Vector2f& p : points_in_robot) {
    if (options_.moved_object_clearance <= 0.0 ||
        !fullest.SeenFree(robot_in_local * Eigen::Vector2d(p.cast<double>()), options_.moved_object_clearance)) {
      kept.push_back(p);
    }
  }
  for (Entry& entry : grids_) {
    entry.grid->AddPoints(kept, free_ends_in_robot, robot_in_local);
    ++entry.scans;
  }
  if (grids_.size() > 1 && grids_.front().scans >= 2 * options_.scans_per_grid) {
    grids_.erase(grids_.begin());
  }
  ++inserted_;
}

}  // namespace fleetmap
