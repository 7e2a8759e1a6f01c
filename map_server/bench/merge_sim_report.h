#ifndef FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_REPORT_H_
#define FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_REPORT_H_

#include <string>
#include <vector>

#include "map_server/bench/merge_sim_scoring.h"

namespace fleetmap {

// The lines of one merge-sim-bench run; `wall` is its wall time in seconds.
void PrintRun(const RunResult& result, double wall);

// One scenario and detection mode over several seeds (nothing for a single run): single runs
// spread by several points of map accuracy, more than most changes move them.
void PrintSummary(const std::string& name, bool detections, const std::vector<RunResult>& runs);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_REPORT_H_
