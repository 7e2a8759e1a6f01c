// MergeEngine: joins on matches alone judged again as the maps grow.
//
// A join on the whole maps matched (merge_engine_whole_map_match.cc) is accepted when nothing
// else explains the two parts' maps as well at that moment. In a building that looks the same
// turned round, that moment can come early: robot3 of department_3robots, 33 m into the north
// corridor, fits the south corridor (mapped end to end by the others) over 92 % of its map,
// while the true alignment lands a quarter of it on their map, too little to count as an
// alternative; the join was 48.9 m / 180 deg off. Once robot3 has driven on, the true alignment
// explains its map as well, and a fresh engine fed everything waits. So such a join is judged
// again by the same whole-map check each time its component has grown by join_review_growth:
// the robot's map against the robots it joined (those joined before it), where the graph puts
// them. A join ambiguous now is withdrawn, as one that detections contradict is
// (merge_engine_withdraw.cc), and the robot waits for evidence that tells the places apart.
// Joins on submap matches are judged so too (review_submap_match_joins): two submaps agreeing
// and nothing else explaining the whole maps as well can come before the robots have driven
// where the other did (building_2robots' robot2 joined 160 m / 180 deg off at t = 105 s, kept
// to the end; session 42). Against them only alignments that explain nearly as much of the
// robot's map compete, and the maps' twins: over the grown maps a short corridor turned round
// about itself fits as consistently where it overlaps, a fifth of the map, which withdrew true
// east_end joins.

#include <algorithm>
#include <vector>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

bool MergeEngine::ReviewMatchOnlyJoins(MergeUpdate* update) {
  if (!(options_.join_review_growth > 1.0) || !(options_.whole_map_ambiguity > 0.0)) return false;
  // The robot joined last among those due: a wrong join is more likely the newest.
  std::string robot;
  int submaps = 0;
  for (const auto& [id, state] : robots_) {
    using Join = RobotState::MatchOnlyJoin;
    const bool reviewed = state->joined_on_matches_alone == Join::kOnWholeMaps ||
                          (options_.review_submap_match_joins &&
                           state->joined_on_matches_alone == Join::kOnSubmapMatches);
    if (!reviewed || known_placements_.count(id) || Root(id) == id) continue;
    // A detection that agrees is evidence the whole maps cannot overrule.
    if (VotesWithin(id).agreeing > 0) continue;
    const int now = FinishedSubmaps(Root(id));
    if (now < options_.join_review_growth * state->join_reviewed_at) continue;
    if (robot.empty() || state->joined_at > robots_.at(robot)->joined_at) {
      robot = id;
      submaps = now;
    }
  }
  if (robot.empty()) return false;
  robots_.at(robot)->join_reviewed_at = submaps;
  // Judged against the robots it joined, as when it joined: a robot joined later, and wrongly,
  // must not make an earlier join look ambiguous (robot2 was split off for robot3's half turn).
  const int64_t joined_at = robots_.at(robot)->joined_at;
  Part rest;
  for (const std::string& m : Members(Root(robot))) {
    if (m == Root(robot) || (m != robot && robots_.at(m)->joined_at < joined_at)) rest.push_back(m);
  }
  const int max_refuted =
      std::max(options_.whole_map_max_refuted, options_.whole_map_match_max_refuted);
  // Both maps are drawn in the component's frame: the join as it stands is the identity.
  const bool on_whole_maps =
      robots_.at(robot)->joined_on_matches_alone == RobotState::MatchOnlyJoin::kOnWholeMaps;
  const WholeMapVerdict verdict =
      SearchWholeMaps(rest, {robot}, Rigid2d(), max_refuted, on_whole_maps);
  if (!verdict.ambiguity) return false;
  Withdraw(robot, EvidenceKind::kCrossMatch,
           "judged again over the grown maps, its join on " +
               std::string(on_whole_maps ? "the whole maps" : "submap matches") + " is " +
               *verdict.ambiguity + "; split off until evidence tells the places apart",
           update);
  return true;
}

}  // namespace fleetmap
