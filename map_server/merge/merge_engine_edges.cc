// MergeEngine: match edges, each measured against the one submap it is tied to.

#include <algorithm>
#include <cmath>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"
#include "shared/matching/degeneracy.h"

namespace fleetmap {

std::shared_ptr<const MatchTarget> MergeEngine::SubmapTarget(const NodeId& id) {
  constexpr size_t kCachedSubmapTargets = 32;
  const Submap& submap = robots_.at(id.robot)->submaps.at(id.submap);
  auto found = submap_targets_.find(id);
  if (found == submap_targets_.end() && submap_targets_.size() >= kCachedSubmapTargets) {
    submap_targets_.erase(std::min_element(
        submap_targets_.begin(), submap_targets_.end(),
        [](const auto& a, const auto& b) { return a.second.last_used < b.second.last_used; }));
  }
  CachedSubmapTarget& cached = submap_targets_[id];
  if (!cached.target || cached.revision != submap.revision) {
    cached.target = std::make_unique<MatchTarget>(submap.grid, options_.match);
    cached.revision = submap.revision;
  }
  cached.last_used = ++submap_target_uses_;
  return cached.target;
}

bool MergeEngine::HasMatchEdge(const NodeId& from, const NodeId& to) const {
  return std::any_of(graph_.edges().begin(), graph_.edges().end(), [&](const RelativeEdge& e) {
    return e.from == from && e.to == to &&
           (e.kind == EdgeKind::kCrossMatch || e.kind == EdgeKind::kDetectionMatch);
  });
}

RelativeEdge MergeEngine::MatchedEdge(const NodeId& from, const NodeId& to,
                                      const Rigid2d& to_in_frame, EdgeKind kind) {
  return RefineMatchedEdge(PrepareMatchedEdge(from, to, to_in_frame, kind));
}

MergeEngine::EdgeToRefine MergeEngine::PrepareMatchedEdge(const NodeId& from, const NodeId& to,
                                                          const Rigid2d& to_in_frame,
                                                          EdgeKind kind) {
  EdgeToRefine prepared;
  prepared.edge = MatchEdge(from, to, kind);
  prepared.edge.to_in_from = graph_.NodePose(from)->inverse() * to_in_frame;
  if (options_.edge_refine_window <= 0.0) return prepared;
  const auto to_box = robots_.at(to.robot)->known_boxes.at(to.submap);
  if (!to_box) return prepared;
  prepared.from_target = SubmapTarget(from);
  prepared.from_grid = &robots_.at(from.robot)->submaps.at(from.submap).grid;
  prepared.from_walls = &SubmapSource(from.robot, from.submap);
  prepared.to_source = &SubmapSource(to.robot, to.submap);
  prepared.to_box = *to_box;
  return prepared;
}

RelativeEdge MergeEngine::RefineMatchedEdge(const EdgeToRefine& prepared) const {
  RelativeEdge edge = prepared.edge;
  if (!prepared.from_target || prepared.from_target->empty()) return edge;
  const MatchTarget& target = *prepared.from_target;
  SearchWindow window;
  window.center = edge.to_in_from;
  window.linear_half_extent = Eigen::Vector2d::Constant(options_.edge_refine_window);
  window.angular_half_extent = options_.edge_refine_angular_window;
  MatchGates gates = options_.verify_gates;
  gates.judge_overlap_only = true;
  // Only the points landing where `from` saw anything say where `to` lies against it; the
  // others would pull towards whatever wall of `from` happens to be near.
  MatchSource seen = *prepared.to_source;
  KeepPointsSeenBy(*prepared.from_grid, window.center, &seen);
  const MatchResult r = target.Match(seen, window, gates);
  // The refinement may leave the window (its last step is unbounded): then it slid.
  const Eigen::Vector2d moved = r.pose.translation() - window.center.translation();
  if (!r.accepted || moved.cwiseAbs().maxCoeff() > options_.edge_refine_window ||
      std::abs(NormalizeAngle(r.pose.rotation() - window.center.rotation())) >
          options_.edge_refine_angular_window) {
    return edge;
  }
  // One submap alone may be a stretch of corridor, free to slide along its axis: along the
  // directions its walls where the two overlap do not face, the composite's answer stays.
  const MatchSource& walls = *prepared.from_walls;
  const Box2d overlap = PlaceBox(prepared.to_box, r.pose);
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  int count = 0;
  for (size_t i = 0; i < walls.fine.size(); ++i) {
    const Eigen::Vector2d& p = walls.fine[i];
    if ((p.array() < overlap.min.array()).any() || (p.array() > overlap.max.array()).any())
      continue;
    scatter += walls.fine_normals[i] * walls.fine_normals[i].transpose();
    ++count;
  }
  if (count == 0) return edge;
  const Eigen::Matrix2d to_frame = r.pose.rotation_matrix();  // the scatter is wanted in to's
  edge.to_in_from = KeepObservedDirections(edge.to_in_from, r.pose,
                                           to_frame.transpose() * (scatter / count) * to_frame,
                                           options_.edge_min_observed_normals);
  return edge;
}

}  // namespace fleetmap
