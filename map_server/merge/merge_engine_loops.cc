// MergeEngine: loop closures within one robot's map (searched in merge_engine_nearby.cc).

#include <algorithm>
#include <cmath>
#include <vector>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {
namespace {

bool Overlaps(const Box2d& a, const Box2d& b) {
  return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
}

}  // namespace

void MergeEngine::PlanLoopClosures(std::vector<NearbySearch>* searches) {
  if (!options_.loop_closures) return;
  int budget = options_.max_loop_searches_per_update;
  for (auto& [robot_id, robot] : robots_) {
    for (int64_t id : std::vector<int64_t>(robot->loop_queue.begin(), robot->loop_queue.end())) {
      const auto pose = graph_.NodePose({robot_id, id});
      if (!pose) continue;
      if (budget-- <= 0) return;
      robot->loop_queue.erase(id);
      const auto bounds = robot->SubmapBounds(id, *pose);
      if (!bounds) continue;
      const Box2d box = Grow(*bounds, 1.0);
      // The robot's own older submaps (not its recent neighbours, which local SLAM already
      // ties to this one) rendered around the new submap.
      // Only the few nearest, so the cost stays bounded however often the robot came back.
      std::vector<std::pair<double, int64_t>> near;
      for (const auto& [old_id, old_box] : robot->known_boxes) {
        if (old_id > id - options_.loop_min_id_gap) break;
        const auto old_pose = graph_.NodePose({robot_id, old_id});
        if (!old_pose || !old_box) continue;
        const Box2d old_bounds = PlaceBox(*old_box, *old_pose);
        if (!Overlaps(old_bounds, box)) continue;
        near.emplace_back((old_pose->translation() - pose->translation()).norm(), old_id);
      }
      if (near.empty()) continue;
      std::sort(near.begin(), near.end());
      near.resize(std::min(near.size(), static_cast<size_t>(options_.loop_max_submaps)));
      std::vector<std::pair<const OccupancyGrid*, Rigid2d>> old_submaps;
      for (const auto& [distance, old_id] : near) {
        old_submaps.emplace_back(&robot->submaps.at(old_id).grid,
                                 *graph_.NodePose({robot_id, old_id}));
      }
      NearbySearch search;
      search.kind = EdgeKind::kLoopClosure;
      search.submap = {robot_id, id};
      search.from = NodeId{robot_id, near.front().second};
      search.make_target = [this, old_submaps, box] {
        LogOddsCanvas canvas(options_.render_resolution);
        for (const auto& [grid, pose] : old_submaps) canvas.AddSubmap(*grid, pose, 1.0f);
        return std::make_unique<MatchTarget>(canvas.ToGrid(options_.render_grid, box),
                                             options_.match);
      };
      search.source = &SubmapSource(robot_id, id);
      search.window.center = *pose;
      search.window.linear_half_extent = options_.local_window;
      search.window.angular_half_extent = options_.local_angular_window;
      searches->push_back(std::move(search));
    }
  }
}

bool MergeEngine::HasPendingWork() const {
  for (const auto& [robot_id, robot] : robots_) {
    const std::string root = Root(robot_id);
    for (int64_t id : robot->cross_queue) {
      if (!graph_.HasNode({robot_id, id})) continue;
      const auto tried = robot->cross_tried.find(id);
      for (const auto& [other, state] : robots_) {
        const std::string other_root = Root(other);
        if (other_root == root || state->submaps.empty()) continue;
        if (tried == robot->cross_tried.end() || CrossSearchDue(tried->second, other_root))
          return true;
      }
    }
    const auto has_node = [&](int64_t id) { return graph_.HasNode({robot_id, id}); };
    if (options_.loop_closures &&
        std::any_of(robot->loop_queue.begin(), robot->loop_queue.end(), has_node)) {
      return true;
    }
    if (options_.local_constraints && Members(root).size() >= 2 &&
        std::any_of(robot->local_queue.begin(), robot->local_queue.end(), has_node)) {
      return true;
    }
  }
  // Alignments held on probation, to be judged now (HoldMatchOnlyJoins(false)).
  if (!hold_match_only_joins_ && !probation_.empty()) return true;
  return !WholeMapMatchesDue().empty();
}

}  // namespace fleetmap
