#ifndef FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_RUN_H_
#define FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_RUN_H_

#include <cstdint>
#include <string>

#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/merge/merge_engine_options.h"
#include "robot_agent/detection/laser_body.h"

namespace fleetmap {

// What one run of fleetmap-merge-sim-bench does: its flags.
struct BenchOptions {
  bool detections = true;
  double feed_period = 5.0;        // seconds of sim time between engine updates
  double detection_period = 1.0;   // one detection per ordered pair per this many seconds
  double detection_sigma = 0.05;   // metres, noise of the synthetic detections
  double outlier_fraction = 0.0;   // detections moved by 1-5 m in a random direction
  double false_translation = 0.5;  // a placed pair further off than this is a false merge
  double false_rotation = 0.087;
  bool verbose = false;
  bool diagnose = false;  // per-submap and per-edge errors against the truth
  bool twins = false;     // each pair's twins at the true anchors (RunResult::pair_twins)
  // Score a fresh engine fed everything at once at the end (the server's rebuild once uploads
  // settle) instead of the engine fed as the run went, when it places at least as many robots.
  bool settled_rebuild = false;
  MergeEngineOptions engine;
  bool mask_seen_robots = true;  // with detections: returns off seen robots kept out of local SLAM
  // Round bodies the laser alone finds masked too (the agent's detection.mask_laser_bodies).
  bool mask_laser_bodies = false;
  LaserBodyOptions laser_bodies;
  uint64_t seed_offset = 0;  // added to the scenario's seed (odometry, laser and route noise)
  std::string algorithm = "scan-matching";  // every robot's local SLAM backend
  int submap_scans = -1;                    // scan-matching submap limits; negative: default
  double submap_travel = -1.0;
  double submap_resolution = -1.0;
};

// Runs one simulator scenario (a file path) through every robot's local SLAM into a MergeEngine
// fed as the run goes, and scores the merge against the simulator's truth.
bool Run(const std::string& scenario, const BenchOptions& options, RunResult* result,
         std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_MERGE_SIM_RUN_H_
