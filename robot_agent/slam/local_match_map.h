#ifndef FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_MATCH_MAP_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_MATCH_MAP_H_

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/slam/return_persistence.h"
#include "robot_agent/slam/small_foreground_objects.h"
#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"

namespace fleetmap {

struct LocalMatchMapOptions {
  // The grids track the space their scans saw (MatchGridOptions::track_observed), only to
  // recognise returns from objects that moved there (see moved_object_clearance).
  MatchGridOptions grid = DefaultGrid();
  // A return that lands inside space the fullest grid saw free (MatchGrid::SeenFree), farther
  // than this (metres) from every obstacle in it, comes from something that moved there
  // (another robot, a person) and is left out of the map: a static wall never appears inside
  // seen free space, and a moving one, kept, drags the next scans' matches along with it
  // (another robot driving towards this one in a corridor made its path 1 % too long). It must
  // stay below how far such an object moves between two insertions (~0.1 m for a robot at
  // walking pace: each new return would otherwise lie next to the last one kept) and above a
  // cell plus the range noise; 0.08 was the best of 0.05 / 0.08 / 0.15 on the simulator's
  // department and rectangle scenarios. 0 keeps every return.
  double moved_object_clearance = 0.08;
  // Returns off small objects in front of their surroundings (SmallForegroundObjects) enter the
  // map only once they persist (ReturnPersistence): off the back of a robot driving ahead the
  // same way they never do. Held back, their beams still mark the space in front of them as
  // seen. Walls go in at once: far down a wall seen at a shallow angle the returns are too sparse
  // for the test, and holding every return back turned the department's robots' headings 2-4
  // times as much (docs/BENCHMARKS.md, issue 8, session 13).
  SmallForegroundObjectOptions small_objects;
  ReturnPersistenceOptions persistence;
  // Each of the two overlapping grids holds up to 2 * scans_per_grid scans; a new grid starts
  // every scans_per_grid scans, so the target always holds between scans_per_grid and
  // 2 * scans_per_grid recent scans.
  int scans_per_grid = 30;

  static MatchGridOptions DefaultGrid();
};

// The map of recent scans a new scan is matched against (Hähnel-style local map). Two
// overlapping distance grids are kept: scans go into both, matching uses the older (fuller) one,
// and when it is full it is dropped. Old, drifted parts of the trajectory never enter the target,
// which is what keeps incremental maximum-likelihood mapping consistent over a long run.
class LocalMatchMap {
 public:
  explicit LocalMatchMap(const LocalMatchMapOptions& options);

  // Follows every scan's returns (robot frame, beam order) taken at `robot_in_local`, and says
  // which of them may go into the map (see small_objects). Call it for every scan, inserted or
  // not: it judges each scan against the one before.
  std::vector<bool> Track(const std::vector<Eigen::Vector2f>& points_in_robot, const Rigid2d& robot_in_local);
  // Which of a scan's returns (robot frame, beam order) taken at `robot_in_local` (e.g. the pose
  // odometry predicts) lie on small objects that moved since the last scan Track saw: none of
  // their returns persists. Records nothing.
  std::vector<bool> Moved(const std::vector<Eigen::Vector2f>& points_in_robot,
                          const Rigid2d& robot_in_local) const;
  // Adds a scan's points (robot frame) taken at `robot_in_local`, those `mappable` says (what
  // Track said of them; empty: all). `free_ends_in_robot`: where the beams that saw nothing end
  // (the range limit), so that the space they crossed counts as seen.
  void Insert(const std::vector<Eigen::Vector2f>& points_in_robot, const std::vector<bool>& mappable,
              const std::vector<Eigen::Vector2f>& free_ends_in_robot, const Rigid2d& robot_in_local);
  // The grid to match against; empty before the first insertion.
  const MatchGrid& target() const { return *grids_.front().grid; }
  int inserted_scans() const { return inserted_; }

 private:
  struct Entry {
    std::unique_ptr<MatchGrid> grid;
    int scans = 0;
  };
  LocalMatchMapOptions options_;
  std::vector<Entry> grids_;  // oldest first; never empty
  ReturnPersistence persistence_;
  int inserted_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_MATCH_MAP_H_
