#ifndef FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_DIAGNOSIS_H_
#define FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_DIAGNOSIS_H_

#include <map>

#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/merge/merge_engine.h"
#include "robot_agent/sim/world.h"
#include "shared/core/submap.h"

namespace fleetmap {

// Where a merge's error comes from, against the simulator's truth (the benches' --diagnose):
// - per submap, how far local SLAM and the merged graph put its anchor, and how far its walls
//   stand, at the true anchor, from the world's (its content, which no merge can undo);
// - per ordered pair of robots, the detections' mean error at the true anchors;
// - the error budget of every pair's first submaps: the graph solved again with the match
//   edges at the truth, with the consecutive-submap edges at the truth (or only their
//   headings), with both at the truth (what the detection edges alone pull), without the
//   detection edges, and without them with the consecutive-submap edges at the truth;
// - per graph edge (but detections), its measurement against the true relation, and for a
//   match edge where its two submaps alone fit best near the truth: near it, the submaps agree
//   and the engine misplaced the edge; far from it, the submaps themselves disagree. For a
//   consecutive-submap edge, where its two submaps fit best near local SLAM's relation: could
//   the merge's matching measure it better than local SLAM did?
// The benches' --diagnose help text.
inline constexpr const char* kDiagnoseHelp =
    "print, against the truth, every submap's anchor error (local SLAM, merged) and wall offset, "
    "the detections' mean error, the pairs' error budget (the graph solved again with match "
    "edges, local SLAM's chains or their headings at the truth, or no detections) and every "
    "graph edge's error, with where its two submaps fit each other (see merge_sim_diagnosis.h)";

void PrintSubmapDiagnosis(const MergeEngine& engine, const std::map<NodeId, Submap>& submaps,
                          const RunTruth& known, const MergeEngineOptions& options,
                          const sim::World& world);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_DIAGNOSIS_H_
