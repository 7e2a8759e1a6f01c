// MergeEngine: one part's whole map matched against another's, for parts no submap places.
//
// In the building every submap is a stretch of plain corridor or a room like the next one: each
// matches the other robot's map at several places (building_2robots: 68 of 74 second peaks at
// 0.95-1.00 of the best), so no submap match passes the ambiguity gate, though both robots drove
// the same corridors. The whole maps are distinctive where their submaps are not. The best
// alignment of one part's whole map on the other's becomes a hypothesis like a submap match, with
// no ambiguity gate of its own: it is accepted only when another submap matches at the pose it
// predicts and the whole-map check (merge_engine_ambiguity.cc) finds no alternative as good, so
// that a department that looks the same turned round still waits.

#include <algorithm>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

namespace {

std::pair<std::string, std::string> PairKey(const std::string& a, const std::string& b) {
  return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
}

}  // namespace

OccupancyGrid MergeEngine::RenderPart(const Part& members, double resolution) const {
  LogOddsCanvas canvas(resolution);
  for (const std::string& m : members) {
    for (const auto& [id, submap] : robots_.at(m)->submaps) {
      if (const auto pose = graph_.NodePose({m, id})) canvas.AddSubmap(submap.grid, *pose, 1.0f);
    }
  }
  OccupancyGridOptions grid_options = options_.render_grid;
  grid_options.resolution = resolution;
  return canvas.ToGrid(grid_options);
}

MatchTargetOptions MergeEngine::WholeMapMatchOptions() const {
  MatchTargetOptions match_options = options_.match;
  match_options.grid.resolution = options_.whole_map_resolution;
  match_options.grid.sigma = 0.0;  // the resolution
  return match_options;
}

std::vector<std::pair<std::string, std::string>> MergeEngine::WholeMapMatchesDue() const {
  std::vector<std::pair<std::string, std::string>> due;
  if (!options_.whole_map_matches) return due;
  std::set<std::string> roots;
  for (const auto& [id, state] : robots_) {
    if (!state->submaps.empty()) roots.insert(Root(id));
  }
  for (auto a = roots.begin(); a != roots.end(); ++a) {
    for (auto b = std::next(a); b != roots.end(); ++b) {
      const int submaps_a = FinishedSubmaps(*a), submaps_b = FinishedSubmaps(*b);
      if (std::min(submaps_a, submaps_b) < options_.whole_map_match_min_submaps) continue;
      const auto tried = whole_map_tried_.find(PairKey(*a, *b));
      const int total = submaps_a + submaps_b;
      if (tried == whole_map_tried_.end() ||
          total >= std::max(tried->second + 1.0, options_.whole_map_match_growth * tried->second)) {
        due.emplace_back(*a, *b);
      }
    }
  }
  return due;
}

int MergeEngine::MaxRefuted(const Hypothesis& h) const {
  return h.whole_maps ? options_.whole_map_match_max_refuted : options_.whole_map_max_refuted;
}

void MergeEngine::ProcessWholeMapMatches(MergeUpdate* update) {
  int budget = options_.max_whole_map_matches_per_update;
  for (const auto& [first, second] : WholeMapMatchesDue()) {
    if (budget-- <= 0) return;
    // A join earlier in this loop may have put both in one part.
    if (Root(first) != first || Root(second) != second) continue;
    // The larger map is the target: the smaller one then lies on it rather than off it.
    const bool first_larger = FinishedSubmaps(first) >= FinishedSubmaps(second);
    const std::string& root_a = first_larger ? first : second;
    const std::string& root_b = first_larger ? second : first;
    whole_map_tried_[PairKey(root_a, root_b)] = FinishedSubmaps(root_a) + FinishedSubmaps(root_b);
    const MatchTargetOptions match_options = WholeMapMatchOptions();
    const MatchTarget target(RenderPart(Members(root_a), options_.whole_map_resolution),
                             match_options);
    MatchSource source = MakeMatchSource(RenderPart(Members(root_b), options_.whole_map_resolution),
                                         Rigid2d(), match_options);
    if (target.empty() || source.coarse.empty()) continue;
    // Turned about its centroid; overlapping only a part of a's map, that centroid can lie off it.
    const Eigen::Vector2d c = Centroid(source.coarse);
    TransformSource(Rigid2d(-c, 0.0), &source);
    SearchWindow window = target.Everywhere();
    window.linear_half_extent += Eigen::Vector2d::Constant(Radius(source.coarse));
    const MatchResult r = target.Match(source, window, options_.whole_map_match_gates);
    ++global_searches_in_turn_;
    if (!r.found) continue;
    const Rigid2d b_in_a = r.pose * Rigid2d(-c, 0.0);
    // The edge ties b's node nearest its map's centre to a's node nearest where that lands.
    const auto to = NearestNode(root_b, "", c);
    if (!to) continue;
    const Rigid2d to_in_a = b_in_a * *graph_.NodePose(*to);
    const auto from = NearestNode(root_a, "", to_in_a.translation());
    if (!from) continue;
    AlignmentEvent event;
    event.evidence = EvidenceKind::kCrossMatch;
    event.robot_a = from->robot;
    event.robot_b = to->robot;
    FillEvent(r, &event);
    event.reason = "whole maps matched: " + event.reason;
    if (!r.accepted) {
      event.type = AlignmentEventType::kRejected;
      update->events.push_back(event);
      continue;
    }
    Hypothesis h;
    h.robot_a = from->robot;
    h.robot_b = to->robot;
    h.whole_maps = true;
    h.local_b_in_local_a = LocalToFrame(h.robot_a)->inverse() * b_in_a * *LocalToFrame(h.robot_b);
    h.edge = MatchedEdge(*from, *to, to_in_a, EdgeKind::kCrossMatch);
    event.local_b_in_local_a = h.local_b_in_local_a;
    h.event = event;
    // A match of the grown maps supersedes the last one between the same parts.
    hypotheses_.erase(std::remove_if(hypotheses_.begin(), hypotheses_.end(),
                                     [&](const Hypothesis& old) {
                                       return old.whole_maps &&
                                              PairKey(Root(old.robot_a), Root(old.robot_b)) ==
                                                  PairKey(root_a, root_b);
                                     }),
                      hypotheses_.end());
    Consider(std::move(h), update);
  }
}

}  // namespace fleetmap
