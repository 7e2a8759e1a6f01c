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
// `mode` says which detections the runs had (DetectionsMode).
void PrintSummary(const std::string& name, const std::string& mode,
                  const std::vector<RunResult>& runs);

// "no detections", "with detections", or "with detections, 10 % corrupted".
std::string DetectionsMode(bool detections, double outlier_fraction);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_REPORT_H_
