#ifndef FLEETMAP_MAP_SERVER_BENCH_MERGE_REPLAY_INPUTS_H_
#define FLEETMAP_MAP_SERVER_BENCH_MERGE_REPLAY_INPUTS_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/store/records.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Everything the merge worker's Rebuild() reads from the store, plus the newest published
// version (what the live server made of the same data).
struct StoreContents {
  std::vector<RobotRecord> robots;
  std::vector<StoredSubmap> submaps;  // latest revisions, in ingest order (seq)
  std::map<std::string, Trajectory> trajectories;
  std::vector<DetectionRecord> detections;
  std::optional<VersionRecord> latest_version;
  std::optional<EncodedGrid> latest_grid;
};

// The simulator's truth folder (fleetmap-sim --out): manifest.yaml, <robot>.gt.txt, world/.
struct TruthFiles {
  std::vector<std::string> names;                // simulator order
  std::vector<std::map<double, Rigid2d>> poses;  // robot in world, by simulator time
  std::string world_path;
};

// False with `error` when the database is missing or unreadable (never creates one).
bool ReadStore(const std::string& path, StoreContents* out, std::string* error);
bool ReadTruthFiles(const std::string& dir, TruthFiles* truth, std::string* error);

// The pose at the truth tick nearest `time`, when one is within 1 ms.
std::optional<Rigid2d> NearestPose(const std::map<double, Rigid2d>& poses, double time);

// RunTruth as merge-sim-bench builds it while simulating, from the stored submaps' scan times;
// `unmatched` counts scan times without a truth tick. False with `error` for a robot of the
// database that the truth does not list.
bool BuildRunTruth(const StoreContents& store, const TruthFiles& files, RunTruth* truth,
                   int* unmatched, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_REPLAY_INPUTS_H_
