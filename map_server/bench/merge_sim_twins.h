#ifndef FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_TWINS_H_
#define FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_TWINS_H_

#include <memory>
#include <optional>
#include <vector>

#include "map_server/merge/match_target.h"
#include "map_server/merge/merge_engine_options.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// The best case for merging two maps without detections: both at their true anchors (no local
// SLAM drift), is there a twin of the true alignment, one map moved by a symmetry of either
// map, that the whole-map check could not rule out? Where one scores nearly as well and its
// walls cross little of the other map's seen-free space, nothing in the maps tells the twin
// from the truth, and no merge on the maps alone can be known correct.
struct PairTwin {
  Rigid2d move;              // the second map moved from its true place (world frame)
  double shift = 0.0;        // metres its points' centroid moves
  double score_ratio = 0.0;  // its score over the second map's points / the truth's
  // Its share of the second map's points landing where the first saw, over the truth's share,
  // and its score per such point over the truth's.
  double overlap_share = 0.0;
  double overlap_score_ratio = 0.0;
  int crossings = 0;        // either map's walls in space the other saw free, at the twin
  int truth_crossings = 0;  // the same at the truth
  // Whether the whole-map check's walls rule it out with the truth as the join: crossings >=
  // overlap_share * whole_map_min_contradictions + whole_map_contradiction_ratio *
  // truth_crossings, the truth crossing at most whole_map_max_join_contradictions.
  bool ruled_out = false;
};

// Per pair of maps (a < b, the order of RunResult::pair_overlap), each at its true anchors in
// the world frame (`targets[i]` and `sources[i]` of map i, as the whole-map check sees a map):
// of the twins that compete with the truth as the whole-map check's alternatives compete with a
// join, the one the walls are least able to rule out; nullopt when none competes. The moves are the
// symmetries of either map and of `all`, every map together (`all_source` its points): two robots
// that each saw one half of a building symmetric under a half turn have maps with no symmetry of
// their own, but b moved by the building's lands where a's map looks as b's does.
std::vector<std::optional<PairTwin>> PairTwins(
    const std::vector<std::unique_ptr<MatchTarget>>& targets,
    const std::vector<MatchSource>& sources, const MatchTarget& all, const MatchSource& all_source,
    const MergeEngineOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_TWINS_H_
