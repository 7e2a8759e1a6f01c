// MergeEngine: loop closures within one robot's map.

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

void MergeEngine::ProcessLoopClosures(MergeUpdate* update) {
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
      Box2d box = *bounds;
      box.min.array() -= 1.0;
      box.max.array() += 1.0;
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
      std::sort(near.begin(), near.end());
      near.resize(std::min(near.size(), static_cast<size_t>(options_.loop_max_submaps)));
      LogOddsCanvas canvas(options_.render_resolution);
      for (const auto& [distance, old_id] : near) {
        canvas.AddSubmap(robot->submaps.at(old_id).grid, *graph_.NodePose({robot_id, old_id}), 1.0f);
      }
      const std::optional<NodeId> nearest =
          near.empty() ? std::nullopt : std::optional<NodeId>(NodeId{robot_id, near.front().second});
      if (!nearest) continue;
      const MatchTarget target(canvas.ToGrid(options_.render_grid, box), options_.match);
      if (target.empty()) continue;
      SearchWindow window;
      window.center = *pose;
      window.linear_half_extent = options_.local_window;
      window.angular_half_extent = options_.local_angular_window;
      const MatchResult r = target.Match(SubmapSource(robot_id, id), window, options_.verify_gates);
      if (!r.accepted) continue;
      graph_.AddEdge(MatchedEdge(*nearest, {robot_id, id}, r.pose, EdgeKind::kLoopClosure));
      graph_dirty_ = true;
      AlignmentEvent event;
      event.type = AlignmentEventType::kConstraintAdded;
      event.evidence = EvidenceKind::kLoopClosure;
      event.robot_a = robot_id;
      event.robot_b = robot_id;
      event.submaps_b = {id};
      event.score = r.score;
      event.overlap = r.overlap;
      event.residual = r.residual;
      event.reason = "loop closure with submap " + std::to_string(nearest->submap) + ": " + r.reason;
      update->events.push_back(event);
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
  return false;
}

}  // namespace fleetmap
