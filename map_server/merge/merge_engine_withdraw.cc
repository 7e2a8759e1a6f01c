// MergeEngine: undoing an accepted alignment that later detections contradict.
//
// Matching can join a robot before any detection of it reaches the server: in a nearly
// symmetric building its map turned round fits as well, and a second matched submap agrees with
// the turned map too. Once joined, each contradicting detection alone is an outlier; many of
// them, and more than agree, mean the join is wrong. The robot is split off (its links to the
// rest removed from the graph) and its detections are judged again, now between two parts, where
// they can place it where they say and veto the wrong match. Withdraw() also undoes joins on the
// whole maps that the grown maps find ambiguous (merge_engine_join_review.cc).

#include <algorithm>
#include <sstream>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

MergeEngine::DetectionVotes MergeEngine::VotesWithin(const std::string& robot) const {
  DetectionVotes votes;
  for (const RobotDetection& d : detections_) {
    const bool observer = d.observer_id == robot, observed = d.observed_id == robot;
    if (!observer && !observed) continue;
    if (Root(observer ? d.observed_id : d.observer_id) != Root(robot)) continue;
    const auto a = RobotInComponent(d.observer_id, d.timestamp);
    const auto b = RobotInComponent(d.observed_id, d.timestamp);
    if (!a || !b) continue;
    ++(DetectionDistance(d, *a, *b) <= options_.detection_gate ? votes.agreeing : votes.contradicting);
  }
  return votes;
}

bool MergeEngine::ReviewJoins(MergeUpdate* update) {
  const bool asked = review_joins_;
  review_joins_ = false;
  if (!asked || options_.min_withdrawing_detections <= 0) return false;
  bool withdrew = false;
  for (size_t round = 0; round < robots_.size(); ++round) {
    // The robot most contradicted; on a tie the one joined last (a two-robot component's
    // votes are the same for both members).
    std::string worst;
    DetectionVotes worst_votes;
    for (const auto& [robot, state] : robots_) {
      if (known_placements_.count(robot) || Members(Root(robot)).size() < 2) continue;
      const DetectionVotes v = VotesWithin(robot);
      if (v.contradicting < options_.min_withdrawing_detections ||
          v.contradicting <= options_.withdraw_majority * v.agreeing) {
        continue;
      }
      const int margin = v.contradicting - v.agreeing;
      const int worst_margin = worst_votes.contradicting - worst_votes.agreeing;
      if (worst.empty() || margin > worst_margin ||
          (margin == worst_margin && state->joined_at > robots_.at(worst)->joined_at)) {
        worst = robot;
        worst_votes = v;
      }
    }
    if (worst.empty()) break;
    std::ostringstream why;
    why << worst_votes.contradicting << " detections between " << worst
        << " and the robots it was joined with contradict the joined map (" << worst_votes.agreeing
        << " agree); split off until evidence agrees again";
    Withdraw(worst, EvidenceKind::kDetection, why.str(), update);
    withdrew = true;
  }
  return withdrew;
}

void MergeEngine::Withdraw(const std::string& robot, EvidenceKind evidence,
                           const std::string& reason, MergeUpdate* update) {
  const std::string old_root = Root(robot);
  const std::vector<std::string> members = Members(old_root);
  RobotState& state = *robots_.at(robot);
  if (IsPlaced(robot)) {
    // The robot leaves the global map: where it was rendered must be drawn again.
    for (const auto& [id, rendered] : state.rendered) {
      Include(&update->changed_region, state.SubmapBounds(id, rendered.pose));
    }
    update->graph_changed = true;
  }
  graph_.DetachRobot(robot);
  for (auto& [id, s] : robots_) s->odometry_edge.clear();
  for (size_t i = 0; i < graph_.edges().size(); ++i) {
    const RelativeEdge& e = graph_.edges()[i];
    if (e.kind == EdgeKind::kOdometry) robots_.at(e.to.robot)->odometry_edge[e.to.submap] = i;
  }

  // The rest may have hung together only through the robot: regroup by the links left.
  std::map<std::string, std::string> parent;
  for (const std::string& m : members) parent[m] = m;
  const auto find = [&](std::string m) {
    while (parent.at(m) != m) m = parent.at(m);
    return m;
  };
  const auto unite = [&](const std::string& a, const std::string& b) {
    if (parent.count(a) && parent.count(b)) parent[find(a)] = find(b);
  };
  for (const RelativeEdge& e : graph_.edges()) unite(e.from.robot, e.to.robot);
  for (const DetectionEdge& e : graph_.detections()) unite(e.observer.robot, e.observed.robot);
  for (const auto& [known, placement] : known_placements_) unite(known, known_root_);
  std::map<std::string, std::vector<std::string>> groups;
  for (const std::string& m : members) groups[find(m)].push_back(m);
  std::set<std::string> new_roots;
  for (const auto& [key, group] : groups) {
    // The old root keeps its part (and with it the global frame); any other part is framed by
    // its member joined earliest.
    std::string root = group.front();
    for (const std::string& m : group) {
      if (m == old_root) {
        root = m;
        break;
      }
      if (robots_.at(m)->joined_at < robots_.at(root)->joined_at) root = m;
    }
    for (const std::string& m : group) {
      root_[m] = root;
      // Their joins were judged with the robot among them: judged again without it.
      robots_.at(m)->join_reviewed_at = 0;
    }
    new_roots.insert(root);
    RobotState& r = *robots_.at(root);
    if (!r.fixed_node) {
      for (const auto& [id, submap] : r.submaps) {
        if (!graph_.HasNode({root, id})) continue;
        r.fixed_node = NodeId{root, id};
        graph_.SetFixed(*r.fixed_node, true);
        break;
      }
    }
  }
  graph_dirty_ = true;

  // Search again what the old grouping had settled, and judge the detections again.
  new_roots.insert(old_root);
  for (auto& [id, s] : robots_) {
    if (std::find(members.begin(), members.end(), id) != members.end()) {
      s->cross_tried.clear();
      continue;
    }
    for (auto& [submap, tried] : s->cross_tried) {
      for (const std::string& r : new_roots) tried.erase(r);
    }
  }
  const std::set<size_t> pending(pending_detections_.begin(), pending_detections_.end());
  for (size_t i = 0; i < detections_.size(); ++i) {
    const RobotDetection& d = detections_[i];
    if ((d.observer_id == robot || d.observed_id == robot) && !pending.count(i)) pending_detections_.push_back(i);
  }

  AlignmentEvent event;
  event.type = AlignmentEventType::kWithdrawn;
  event.evidence = evidence;
  // The part it left: the old root's, or, when the robot was that root, another member's.
  event.robot_a = old_root;
  if (old_root == robot) {
    const auto other = std::find_if(members.begin(), members.end(), [&](const std::string& m) { return m != robot; });
    if (other != members.end()) event.robot_a = Root(*other);
  }
  event.robot_b = robot;
  event.reason = reason;
  update->events.push_back(event);
}

}  // namespace fleetmap
