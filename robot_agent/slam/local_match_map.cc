#include "robot_agent/slam/local_match_map.h"

#include <algorithm>

namespace fleetmap {
namespace {

std::vector<Eigen::Vector2d> InLocal(const std::vector<Eigen::Vector2f>& points_in_robot,
                                     const Rigid2d& robot_in_local) {
  std::vector<Eigen::Vector2d> in_local;
  in_local.reserve(points_in_robot.size());
  for (const Eigen::Vector2f& p : points_in_robot) in_local.push_back(robot_in_local * Eigen::Vector2d(p.cast<double>()));
  return in_local;
}

// How far short of a held-back return (metres, two cells) its beam marks space as seen.
constexpr float kHeldBackShortfall = 0.1f;

}  // namespace

MatchGridOptions LocalMatchMapOptions::DefaultGrid() {
  MatchGridOptions options;
  // 2.5 cm cells, seen space in 5 cm blocks (session 29, shipped in session 31): the field near
  // a wall steps less where one scan's wall piece meets another's, and local SLAM's heading
  // wander falls by 40 % (0.063 -> 0.038 deg RMS over 40 simulated runs), which lifts every
  // simulated merge with detections above 98 % (docs/BENCHMARKS.md, issues 4 and 8).
  options.resolution = 0.025;
  options.observed_block = 2;
  options.track_observed = true;
  // Seen space is only for recognising moved objects: searches keep scoring unseen cells 0.
  options.unknown_score = 0.0f;
  return options;
}

LocalMatchMap::LocalMatchMap(const LocalMatchMapOptions& options)
    : options_(options), persistence_(options.persistence) {
  options_.scans_per_grid = std::max(1, options_.scans_per_grid);
  grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
}

std::vector<bool> LocalMatchMap::Track(const std::vector<Eigen::Vector2f>& points_in_robot,
                                       const Rigid2d& robot_in_local) {
  std::vector<bool> mappable =
      persistence_.Observe(InLocal(points_in_robot, robot_in_local), robot_in_local.translation());
  const std::vector<bool> small = SmallForegroundObjects(points_in_robot, options_.small_objects);
  for (size_t i = 0; i < mappable.size(); ++i) mappable[i] = mappable[i] || !small[i];
  return mappable;
}

std::vector<bool> LocalMatchMap::Moved(const std::vector<Eigen::Vector2f>& points_in_robot,
                                       const Rigid2d& robot_in_local) const {
  const std::vector<bool> persisted = persistence_.Persisted(InLocal(points_in_robot, robot_in_local));
  const std::vector<int> object = SmallForegroundObjectIds(points_in_robot, options_.small_objects);
  // Moved: none of its returns lies where the last scan saw a surface. A door jamb coming out
  // from behind a wall's corner shows a new part of its face, but also the part seen before.
  std::vector<bool> seen_before(object.size(), false);  // by object id (fewer than returns)
  for (size_t i = 0; i < object.size(); ++i) {
    if (object[i] >= 0 && persisted[i]) seen_before[static_cast<size_t>(object[i])] = true;
  }
  std::vector<bool> moved(object.size(), false);
  for (size_t i = 0; i < object.size(); ++i) {
    moved[i] = object[i] >= 0 && !seen_before[static_cast<size_t>(object[i])];
  }
  return moved;
}

void LocalMatchMap::Insert(const std::vector<Eigen::Vector2f>& points_in_robot,
                           const std::vector<bool>& mappable,
                           const std::vector<Eigen::Vector2f>& free_ends_in_robot,
                           const Rigid2d& robot_in_local) {
  if (grids_.back().scans >= options_.scans_per_grid) {
    grids_.push_back({std::make_unique<MatchGrid>(options_.grid), 0});
  }
  // Decided once, against the fullest grid, so that a grid started a moment ago (which has seen
  // nothing yet) does not map the moving object either.
  std::vector<Eigen::Vector2f> kept;
  kept.reserve(points_in_robot.size());
  std::vector<Eigen::Vector2f> seen = free_ends_in_robot;
  const MatchGrid& fullest = *grids_.front().grid;
  for (size_t i = 0; i < points_in_robot.size(); ++i) {
    if (i < mappable.size() && !mappable[i]) {
      // Held back, but the space in front of it was seen: an oncoming robot then steps into
      // space the map knows is free (see moved_object_clearance). A cell short of the return,
      // so that a pillar held back for a moment is not then taken for a moving object itself.
      const float range = points_in_robot[i].norm();
      if (range > kHeldBackShortfall) seen.push_back(points_in_robot[i] * ((range - kHeldBackShortfall) / range));
      continue;
    }
    if (options_.moved_object_clearance <= 0.0 ||
        !fullest.SeenFree(robot_in_local * Eigen::Vector2d(points_in_robot[i].cast<double>()), options_.moved_object_clearance)) {
      kept.push_back(points_in_robot[i]);
    }
  }
  // The grids share their options: the scan is fitted to its walls once for all of them.
  const MatchGridBatch batch = grids_.front().grid->PrepareScan(kept, seen, robot_in_local);
  for (Entry& entry : grids_) {
    entry.grid->Add(batch);
    ++entry.scans;
  }
  if (grids_.size() > 1 && grids_.front().scans >= 2 * options_.scans_per_grid) {
    grids_.erase(grids_.begin());
  }
  ++inserted_;
}

}  // namespace fleetmap
