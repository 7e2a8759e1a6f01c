// fleetmap-merge-replay: a finished end-to-end run (the server's SQLite database plus the
// simulator's ground truth) replayed into a fresh MergeEngine and scored as merge-sim-bench scores
// its in-process runs, to tell whether the agents' local maps or the merge lose map accuracy.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "map_server/bench/engine_flags.h"
#include "map_server/bench/merge_replay_inputs.h"
#include "map_server/bench/merge_sim_diagnosis.h"
#include "map_server/bench/merge_sim_report.h"
#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/merge/merge_engine.h"
#include "robot_agent/sim/map_accuracy.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world_io.h"

namespace fleetmap {
namespace {

constexpr double kFalseTranslation = 0.5;  // the bench's false-merge thresholds
constexpr double kFalseRotation = 0.087;

// Update() until the engine has no postponed work; the time of each call into `update_ms`.
void UpdateUntilDone(MergeEngine* engine, std::vector<double>* update_ms) {
  const size_t limit = update_ms->size() + 10000;
  do {
    const auto start = std::chrono::steady_clock::now();
    engine->Update();
    update_ms->push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  } while (engine->HasPendingWork() && update_ms->size() < limit);
}

// The worker's Rebuild() order: known placements, submaps by seq, trajectories, detections; then
// Update() until the engine has no postponed work. `one_at_a_time`: Update() after each submap
// too, as a live server folds in uploads as they come.
void Replay(const StoreContents& store, bool one_at_a_time, MergeEngine* engine,
            RunResult* result) {
  std::string error;
  for (const RobotRecord& robot : store.robots) {
    if (robot.local_in_global) engine->SetKnownPlacement(robot.robot_id, *robot.local_in_global);
  }
  std::vector<double> update_ms;
  for (const StoredSubmap& stored : store.submaps) {
    if (!engine->AddOrUpdateSubmap(stored.submap, &error)) {
      std::cerr << "merge_replay: engine refused submap " << stored.submap.robot_id << "/"
                << stored.submap.submap_id << ": " << error << "\n";
    }
    result->submaps += stored.submap.finished;
    if (one_at_a_time) UpdateUntilDone(engine, &update_ms);
  }
  for (const auto& [robot, trajectory] : store.trajectories) {
    if (!engine->SetTrajectory(robot, trajectory, &error)) {
      std::cerr << "merge_replay: engine refused the trajectory of " << robot << ": " << error
                << "\n";
    }
  }
  for (const DetectionRecord& record : store.detections) engine->AddDetection(record.detection);
  UpdateUntilDone(engine, &update_ms);
  result->median_update_ms = Median(update_ms);
  result->max_update_ms = *std::max_element(update_ms.begin(), update_ms.end());
  // All at once, the first Update() folds every submap in.
  result->median_fold_ms =
      result->submaps > 0 && !one_at_a_time ? update_ms.front() / result->submaps : 0.0;
}

// The agents' local SLAM end-pose error, the start placed true (as the bench prints it).
void AddDriftLines(const StoreContents& store, const TruthFiles& files, const RunTruth& truth,
                   RunResult* result) {
  for (size_t i = 0; i < files.names.size(); ++i) {
    const auto trajectory = store.trajectories.find(files.names[i]);
    if (trajectory == store.trajectories.end() || trajectory->second.empty() ||
        !truth.local_in_world[i]) {
      continue;
    }
    const StampedPose& last = trajectory->second.back();
    const auto true_end = NearestPose(files.poses[i], last.timestamp);
    if (!true_end) continue;
    const Rigid2d end = *truth.local_in_world[i] * last.pose;
    char line[160];
    std::snprintf(line, sizeof(line), "  %s local SLAM end-pose error %.3f m, %.2f deg",
                  files.names[i].c_str(), (end.translation() - true_end->translation()).norm(),
                  std::abs(NormalizeAngle(end.rotation() - true_end->rotation())) * 180.0 / M_PI);
    result->lines.push_back(line);
    result->sim_seconds = std::max(result->sim_seconds, last.timestamp);
  }
}

// The live server's newest version with the replay's scorer: the same data merged incrementally
// as it arrived, against the replay's merge of everything at once.
void PrintStoredVersion(const StoreContents& store, const RunTruth& truth,
                        const sim::World& world) {
  if (!store.latest_version || !store.latest_grid) {
    std::printf("  live server: no stored version with a grid\n");
    return;
  }
  const VersionRecord& version = *store.latest_version;
  const auto reference = std::find_if(version.placements.begin(), version.placements.end(),
                                      [](const auto& p) { return p.source == "reference"; });
  const size_t ref = reference == version.placements.end()
                         ? truth.names.size()
                         : static_cast<size_t>(std::find(truth.names.begin(), truth.names.end(),
                                                         reference->robot_id) -
                                               truth.names.begin());
  OccupancyGrid grid;
  std::string error;
  GridDecodeError code;
  if (ref == truth.names.size() || !truth.local_in_world[ref] ||
      !DecodeGrid(*store.latest_grid, GridLimits(), OccupancyGridOptions(), &grid, &code, &error)) {
    std::printf("  live server: version %lld not scored (no reference robot or grid) %s\n",
                static_cast<long long>(version.version), error.c_str());
    return;
  }
  // As ScoreMerge places the engine's map: the global frame is the reference's local frame.
  const Rigid2d& global_in_world = *truth.local_in_world[ref];
  const WallMask walls = sim::WorldWalls(world);
  std::printf(
      "  live server version %lld (reference %s): map within 1 cell of a wall %.2f %% "
      "(best rigid fit %.2f %%)\n",
      static_cast<long long>(version.version), reference->robot_id.c_str(),
      100.0 * ScoreOnWalls(grid, global_in_world, walls).fraction(),
      100.0 * ScoreOnWallsBestFit(grid, global_in_world, walls).fraction());
}

bool LoadScoringWorld(const std::string& scenario, const std::string& truth_world,
                      sim::World* world, std::string* error) {
  if (scenario.empty()) return sim::LoadWorld(truth_world, world, error);
  std::string path = scenario;
  if (path.find('/') == std::string::npos) path = sim::ShippedScenariosDir() + "/" + path + ".yaml";
  sim::Scenario loaded;
  return sim::LoadScenario(path, &loaded, error) && sim::LoadWorld(loaded.world_path, world, error);
}

int Run(const std::string& db, const std::string& truth_dir, const std::string& scenario,
        const MergeEngineOptions& options, bool one_at_a_time, bool diagnose) {
  const auto wall_start = std::chrono::steady_clock::now();
  std::string error;
  StoreContents store;
  TruthFiles files;
  sim::World world;
  RunTruth truth;
  int unmatched = 0;
  if (!ReadStore(db, &store, &error) || !ReadTruthFiles(truth_dir, &files, &error) ||
      !LoadScoringWorld(scenario, files.world_path, &world, &error) ||
      !BuildRunTruth(store, files, &truth, &unmatched, &error)) {
    std::cerr << "merge_replay: " << error << "\n";
    return 1;
  }
  std::printf(
      "%s: %zu robots, %zu submaps, %zu detections; scan times without a truth tick "
      "within 1 ms: %d\n",
      db.c_str(), store.robots.size(), store.submaps.size(), store.detections.size(), unmatched);
  std::map<NodeId, Submap> latest;
  for (const StoredSubmap& s : store.submaps) {
    latest[NodeId{s.submap.robot_id, s.submap.submap_id}] = s.submap;
  }
  RunResult result;
  AddDriftLines(store, files, truth, &result);
  MergeEngine engine(options);
  Replay(store, one_at_a_time, &engine, &result);
  ScoreMapBounds(latest, truth, world, &result);
  ScoreMerge(engine, truth, world, kFalseTranslation, kFalseRotation, &result, &error);
  if (diagnose) PrintSubmapDiagnosis(engine, latest, truth, options, world);
  PrintStoredVersion(store, truth, world);
  PrintRun(result,
           std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) {
  std::string db, truth, scenario;
  bool diagnose = false, one_at_a_time = false;
  fleetmap::MergeEngineOptions options;
  CLI::App app{
      "replays a finished run's server database into a fresh MergeEngine and scores the "
      "agents' local maps and the merge against the simulator's ground truth"};
  app.add_option("--db", db, "the server's SQLite database after the run")->required();
  app.add_option("--truth", truth,
                 "the simulator's truth folder (manifest.yaml, robotN.gt.txt, world/)")
      ->required();
  app.add_option("--scenario", scenario,
                 "score against this scenario's world (file or shipped name) instead of the "
                 "truth folder's");
  app.add_flag("--one-at-a-time", one_at_a_time,
               "feed the submaps one at a time in the order they reached the server, with "
               "Update() after each, as a live server folds uploads in (default: all at once)");
  fleetmap::AddEngineFlags(&app, &options);
  app.add_flag("--diagnose", diagnose, fleetmap::kDiagnoseHelp);
  CLI11_PARSE(app, argc, argv);
  return fleetmap::Run(db, truth, scenario, options, one_at_a_time, diagnose);
}
