// MergeEngine: hypotheses waiting for a second piece of evidence, accepting alignments, and
// the searches that produce evidence without detections.

#include <algorithm>
#include <cmath>
#include <sstream>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

MergeEngine::DetectionVotes MergeEngine::DetectionsAbout(const Hypothesis& h) const {
  DetectionVotes votes;
  const std::string root_a = Root(h.robot_a), root_b = Root(h.robot_b);
  const Rigid2d b_in_a = FrameTransform(h);
  // Both robots' poses in root_a's frame, as they would be if h were accepted.
  auto in_a = [&](const std::string& robot, double time) -> std::optional<Rigid2d> {
    const auto pose = RobotInComponent(robot, time);
    if (!pose) return std::nullopt;
    return Root(robot) == root_a ? *pose : b_in_a * *pose;
  };
  for (const RobotDetection& d : detections_) {
    const std::string observer = Root(d.observer_id), observed = Root(d.observed_id);
    const bool across = (observer == root_a && observed == root_b) || (observer == root_b && observed == root_a);
    if (!across) continue;
    const auto a = in_a(d.observer_id, d.timestamp), b = in_a(d.observed_id, d.timestamp);
    if (!a || !b) continue;
    ++(DetectionDistance(d, *a, *b) <= options_.detection_gate ? votes.agreeing : votes.contradicting);
  }
  return votes;
}

void MergeEngine::Consider(Hypothesis h, MergeUpdate* update) {
  // Detections already received between the two parts overrule a match that contradicts them:
  // in a nearly symmetric building every submap agrees with the map turned round, so a second
  // matched submap cannot tell, and once joined the detections would only be rejected as
  // outliers (department_3robots through the real server: robot3 placed 48.9 m / 180 deg off).
  const DetectionVotes votes = DetectionsAbout(h);
  if (votes.contradicting >= options_.min_contradicting_detections && votes.contradicting > votes.agreeing) {
    h.event.type = AlignmentEventType::kRejected;
    std::ostringstream os;
    os << "; contradicted by " << votes.contradicting << " detections (" << votes.agreeing << " agree)";
    h.event.reason += os.str();
    update->events.push_back(h.event);
    return;
  }
  for (auto it = hypotheses_.begin(); it != hypotheses_.end(); ++it) {
    if (!Agree(h, *it)) continue;
    if (!h.detection && !it->detection) {
      const WholeMapVerdict whole =
          WholeMapAmbiguity(Root(h.robot_a), Root(h.robot_b), FrameTransform(h), MaxRefuted(h));
      if (whole.ambiguity) {
        h.event.type = AlignmentEventType::kHypothesis;
        h.event.reason +=
            "; agrees with another submap match but " + *whole.ambiguity + ": kept as a hypothesis";
        update->events.push_back(h.event);
        hypotheses_.push_back(std::move(h));
        return;
      }
      if (!whole.note.empty()) h.event.reason += "; " + whole.note;
      if (HeldOnProbation(&h, {it->edge}, update)) {
        hypotheses_.push_back(std::move(h));
        return;
      }
    }
    const Hypothesis other = *it;
    hypotheses_.erase(it);
    h.event.reason += "; confirmed by an independent " +
                      std::string(other.detection ? "detection" : "submap match") + " (" + other.event.reason + ")";
    Accept(h, {}, update);
    graph_.AddEdge(other.edge);
    if (other.detection_edge) graph_.AddDetection(*other.detection_edge);
    return;
  }
  std::vector<RelativeEdge> edges;
  if (h.detection && Verify(h, &edges)) {
    h.event.reason += "; confirmed by matching another submap of " + h.robot_b;
    Accept(h, edges, update);
    return;
  }
  if (!h.detection && options_.verify_matches) {
    h.reviewed_at_submaps = FinishedSubmaps(Root(h.robot_a)) + FinishedSubmaps(Root(h.robot_b));
    if (Verify(h, &edges)) {
      const WholeMapVerdict whole =
          WholeMapAmbiguity(Root(h.robot_a), Root(h.robot_b), FrameTransform(h), MaxRefuted(h));
      if (!whole.ambiguity) {
        h.event.reason += "; confirmed by matching another submap of " + h.robot_b;
        if (!whole.note.empty()) h.event.reason += "; " + whole.note;
        if (!HeldOnProbation(&h, edges, update)) {
          Accept(h, edges, update);
          return;
        }
        hypotheses_.push_back(std::move(h));
        return;
      }
      h.event.reason +=
          "; another submap of " + h.robot_b + " matches there too, but " + *whole.ambiguity;
    }
  }
  h.event.type = AlignmentEventType::kHypothesis;
  h.event.reason += "; kept as a hypothesis until a second, independent piece of evidence agrees";
  update->events.push_back(h.event);
  hypotheses_.push_back(std::move(h));
}

bool MergeEngine::Verify(const Hypothesis& h, std::vector<RelativeEdge>* edges) {
  const Rigid2d b_in_a = FrameTransform(h);
  std::vector<std::pair<int64_t, int64_t>> candidates;  // (distance in ids, id)
  const int64_t used = h.submaps_b.empty() ? 0 : *h.submaps_b.begin();
  for (const auto& [id, submap] : robots_.at(h.robot_b)->submaps) {
    if (h.submaps_b.count(id) || !submap.finished || !graph_.HasNode({h.robot_b, id})) continue;
    // A detection is evidence of its own; a match is confirmed only by a submap that shows other
    // walls than the matched one (MergeEngineOptions::verify_max_seen_before).
    if (!h.detection && MostlySeenBefore(h.robot_b, id, h.submaps_b)) continue;
    // A whole-map alignment was not found near any one submap: only those it lands on a's map
    // can confirm it. Those off it used up the attempts, and a robot that started where the
    // other never drove waited however well its later submaps fit (building_4robots +4, robot4
    // on robot2, in a scratch build of session 41). Those landing most on a's map are not the
    // ones to try first: so ordered, building_4robots +0 merged none of its 6 pairs (6 / 6 in id
    // order; why was not examined).
    if (h.whole_maps && ShareOnPart(h.robot_b, id, b_in_a * *graph_.NodePose({h.robot_b, id}),
                                    Root(h.robot_a)) < options_.verify_gates.min_overlap) {
      continue;
    }
    candidates.emplace_back(std::abs(id - used), id);
  }
  std::sort(candidates.begin(), candidates.end());
  int attempts = 0;
  for (const auto& [distance, id] : candidates) {
    if (attempts >= 4) break;
    const Submap& submap = robots_.at(h.robot_b)->submaps.at(id);
    const Rigid2d predicted = b_in_a * *graph_.NodePose({h.robot_b, id});
    const auto bounds = PlacedBounds(submap.grid, predicted);
    if (!bounds) continue;
    ++attempts;
    const auto target = CroppedTarget(Root(h.robot_a), "", Grow(*bounds, 1.0));
    SearchWindow window;
    window.center = predicted;
    window.linear_half_extent = options_.local_window;
    window.angular_half_extent = options_.local_angular_window;
    const MatchResult r = target->Match(SubmapSource(h.robot_b, id), window, options_.verify_gates);
    if (!r.accepted || (r.pose.translation() - predicted.translation()).norm() > options_.agreement_translation ||
        std::abs(NormalizeAngle(r.pose.rotation() - predicted.rotation())) > options_.agreement_rotation) {
      continue;
    }
    const auto from = NearestNode(Root(h.robot_a), "", r.pose.translation());
    if (!from) continue;
    edges->push_back(MatchedEdge(*from, {h.robot_b, id}, r.pose, EdgeKind::kCrossMatch));
    return true;
  }
  return false;
}

bool MergeEngine::MostlySeenBefore(const std::string& robot, int64_t id,
                                   const std::set<int64_t>& seen) const {
  const auto pose = graph_.NodePose({robot, id});
  if (!pose) return true;
  const RobotState& state = *robots_.at(robot);
  // The seen submaps' grids, each with the map from robot frame to grid frame.
  std::vector<std::pair<const OccupancyGrid*, Rigid2d>> seen_grids;
  for (int64_t other : seen) {
    const auto other_pose = graph_.NodePose({robot, other});
    const auto found = state.submaps.find(other);
    if (other_pose && found != state.submaps.end())
      seen_grids.emplace_back(&found->second.grid, other_pose->inverse());
  }
  const std::vector<Eigen::Vector2d> walls =
      OccupiedPoints(state.submaps.at(id).grid, options_.match.grid.occupied_log_odds, *pose);
  if (walls.empty()) return true;
  size_t known = 0;
  for (const Eigen::Vector2d& p : walls) {
    for (const auto& [grid, to_grid] : seen_grids) {
      const CellIndex cell = grid->CellAt(to_grid * p);
      if (grid->Contains(cell) && grid->IsKnown(cell)) {
        ++known;
        break;
      }
    }
  }
  return static_cast<double>(known) >
         options_.verify_max_seen_before * static_cast<double>(walls.size());
}

double MergeEngine::ShareOnPart(const std::string& robot, int64_t id,
                                const Rigid2d& submap_to_frame, const std::string& root) const {
  const std::vector<Eigen::Vector2d> walls =
      OccupiedPoints(robots_.at(robot)->submaps.at(id).grid, options_.match.grid.occupied_log_odds,
                     submap_to_frame);
  if (walls.empty()) return 0.0;
  size_t observed = 0;
  for (const Eigen::Vector2d& p : walls) {
    for (const std::string& m : Members(root)) {
      if (robots_.at(m)->canvas.ObservedAt(p)) {
        ++observed;
        break;
      }
    }
  }
  return static_cast<double>(observed) / static_cast<double>(walls.size());
}

void MergeEngine::Accept(const Hypothesis& h, const std::vector<RelativeEdge>& extra, MergeUpdate* update) {
  const std::vector<std::string> joined =
      JoinComponents(Root(h.robot_a), Root(h.robot_b), FrameTransform(h));
  // A join on matches alone is judged again as the maps grow (merge_engine_join_review.cc).
  const int submaps = FinishedSubmaps(Root(h.robot_a));
  // Alignments on probation between what is now one part are settled.
  probation_.erase(
      std::remove_if(probation_.begin(), probation_.end(),
                     [&](const Hypothesis& p) { return Root(p.robot_a) == Root(p.robot_b); }),
      probation_.end());
  for (const std::string& m : joined) {
    RobotState& state = *robots_.at(m);
    state.joined_on_matches_alone = h.detection    ? RobotState::MatchOnlyJoin::kNo
                                    : h.whole_maps ? RobotState::MatchOnlyJoin::kOnWholeMaps
                                                   : RobotState::MatchOnlyJoin::kOnSubmapMatches;
    state.join_reviewed_at = submaps;
  }
  // The joined robots' maps move into the part's frame now: what is matched against the part
  // later in this update (other reviews, searches, local constraints) must see them there.
  RefreshCanvases(update);
  graph_.AddEdge(h.edge);
  for (const RelativeEdge& e : extra) graph_.AddEdge(e);
  if (h.detection_edge) graph_.AddDetection(*h.detection_edge);
  graph_dirty_ = true;
  AlignmentEvent event = h.event;
  event.type = AlignmentEventType::kAlignmentAccepted;
  update->events.push_back(event);
  // Hypotheses between parts that are now joined either agree with the alignment (and become
  // constraints) or contradict it (and are dropped, saying so).
  std::vector<Hypothesis> kept;
  for (Hypothesis& other : hypotheses_) {
    if (Root(other.robot_a) != Root(other.robot_b)) {
      kept.push_back(std::move(other));
      continue;
    }
    const Rigid2d current = LocalToFrame(other.robot_a)->inverse() * *LocalToFrame(other.robot_b);
    const Rigid2d diff = other.local_b_in_local_a.inverse() * current;
    AlignmentEvent e = other.event;
    if (diff.translation().norm() <= options_.agreement_translation &&
        std::abs(diff.rotation()) <= options_.agreement_rotation) {
      graph_.AddEdge(other.edge);
      if (other.detection_edge) graph_.AddDetection(*other.detection_edge);
      e.type = AlignmentEventType::kConstraintAdded;
      e.reason = "earlier hypothesis agrees with the accepted alignment";
    } else {
      e.type = AlignmentEventType::kRejected;
      e.reason = "earlier hypothesis contradicts the accepted alignment";
    }
    update->events.push_back(e);
  }
  hypotheses_ = std::move(kept);
}

void MergeEngine::ProcessCrossMatches(MergeUpdate* update) {
  const std::map<CrossKey, SearchedAhead> ahead =
      options_.search_ahead ? SearchCrossMatchesAhead() : std::map<CrossKey, SearchedAhead>();
  int budget = options_.max_global_searches_per_update;
  for (auto& [robot_id, robot] : robots_) {
    for (int64_t id : std::vector<int64_t>(robot->cross_queue.begin(), robot->cross_queue.end())) {
      if (!graph_.HasNode({robot_id, id})) continue;
      const std::set<std::string> roots = OtherRoots(robot_id);
      for (const std::string& root : roots) {
        if (Root(robot_id) == root || !CrossSearchDue(robot->cross_tried[id], root)) continue;
        if (budget-- <= 0) return;
        robot->cross_tried[id][root] = FinishedSubmaps(root);
        const MatchTarget& target = Target(root);
        if (target.empty()) continue;
        // Searched ahead unless a join earlier in this loop changed the map searched.
        const auto early = ahead.find({robot_id, id, root, CanvasStamp(root)});
        MatchResult r;
        Eigen::Vector2d c;
        if (early != ahead.end()) {
          r = early->second.result;
          c = early->second.centroid;
        } else {
          const GlobalSearch search = PrepareGlobalSearch(robot_id, id, target);
          r = target.Match(search.source, search.window, options_.cross_gates);
          c = search.centroid;
          ++global_searches_in_turn_;
        }
        AlignmentEvent event;
        event.evidence = EvidenceKind::kCrossMatch;
        event.robot_b = robot_id;
        event.submaps_b = {id};
        FillEvent(r, &event);
        if (!r.found) continue;  // nothing resembling a match: not worth a line of provenance
        const Rigid2d submap_in_frame = r.pose * Rigid2d(-c, 0.0);
        const auto from = NearestNode(root, "", submap_in_frame.translation());
        if (!from) continue;
        event.robot_a = from->robot;
        if (!r.accepted) {
          event.type = AlignmentEventType::kRejected;
          update->events.push_back(event);
          continue;
        }
        const Rigid2d b_frame_in_a_frame = submap_in_frame * graph_.NodePose({robot_id, id})->inverse();
        Hypothesis h;
        h.robot_a = from->robot;
        h.robot_b = robot_id;
        h.local_b_in_local_a = LocalToFrame(h.robot_a)->inverse() * b_frame_in_a_frame * *LocalToFrame(robot_id);
        h.submaps_b = {id};
        h.edge = MatchedEdge(*from, {robot_id, id}, submap_in_frame, EdgeKind::kCrossMatch);
        event.local_b_in_local_a = h.local_b_in_local_a;
        h.event = event;
        // A search again over a grown map supersedes what this submap's last search left waiting.
        hypotheses_.erase(std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                                         [&](const Hypothesis& old) {
                                           return !old.detection && old.robot_b == robot_id &&
                                                  old.submaps_b == h.submaps_b &&
                                                  Root(old.robot_a) == root;
                                         }),
                          hypotheses_.end());
        Consider(std::move(h), update);
      }
    }
  }
}

std::set<std::string> MergeEngine::OtherRoots(const std::string& robot) const {
  std::set<std::string> roots;
  for (const auto& [other, state] : robots_) {
    if (Root(other) != Root(robot) && !state->submaps.empty()) roots.insert(Root(other));
  }
  return roots;
}

int MergeEngine::FinishedSubmaps(const std::string& root) const {
  int n = 0;
  for (const std::string& m : Members(root)) {
    for (const auto& [id, submap] : robots_.at(m)->submaps) n += submap.finished;
  }
  return n;
}

bool MergeEngine::CrossSearchDue(const std::map<std::string, int>& tried,
                                 const std::string& root) const {
  const auto it = tried.find(root);
  if (it == tried.end()) return true;
  return options_.cross_retry_growth > 0.0 &&
         FinishedSubmaps(root) >=
             std::max(it->second + 1.0, options_.cross_retry_growth * it->second);
}

void MergeEngine::ReviewMatchHypotheses(MergeUpdate* update) {
  if (!options_.verify_matches) return;
  for (int review = 0; review < options_.max_hypothesis_reviews_per_update; ++review) {
    // The match checked longest ago goes first, so that none waits behind the others.
    auto next = hypotheses_.end();
    int next_submaps = 0;
    for (auto it = hypotheses_.begin(); it != hypotheses_.end(); ++it) {
      const std::string root_a = Root(it->robot_a), root_b = Root(it->robot_b);
      if (it->detection || root_a == root_b) continue;
      const int submaps = FinishedSubmaps(root_a) + FinishedSubmaps(root_b);
      if (submaps < it->reviewed_at_submaps + options_.review_min_new_submaps) continue;
      if (ProbationRunning(*it)) continue;  // judged again when the maps have grown enough
      if (next == hypotheses_.end() || it->reviewed_at_submaps < next->reviewed_at_submaps) {
        next = it;
        next_submaps = submaps;
      }
    }
    if (next == hypotheses_.end()) return;
    next->reviewed_at_submaps = next_submaps;
    std::vector<RelativeEdge> edges;
    const std::string root_a = Root(next->robot_a), root_b = Root(next->robot_b);
    if (!Verify(*next, &edges)) continue;
    const WholeMapVerdict whole =
        WholeMapAmbiguity(root_a, root_b, FrameTransform(*next), MaxRefuted(*next));
    if (whole.ambiguity) continue;
    Hypothesis h = *next;
    h.event.reason += "; confirmed later by matching another submap of " + h.robot_b +
                      ", nothing as good over the whole maps";
    if (!whole.note.empty()) h.event.reason += " (" + whole.note + ")";
    if (HeldOnProbation(&h, edges, update)) continue;
    hypotheses_.erase(next);
    Accept(h, edges, update);
  }
}

}  // namespace fleetmap
