// fleetmap-merge-sim-bench's run, step by step: the class behind Run() (merge_sim_run.h).
// Driving the simulator and local SLAM into the engine is sim_run.cc; the false joins noted as
// the run goes sim_run_false_joins.cc; settling and scoring sim_run_score.cc.

#ifndef FLEETMAP_MAP_SERVER_BENCH_SIM_RUN_H_
#define FLEETMAP_MAP_SERVER_BENCH_SIM_RUN_H_

#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "map_server/bench/merge_sim_run.h"
#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/merge/merge_engine.h"
#include "robot_agent/sim/simulation.h"
#include "robot_agent/slam/local_slam.h"
#include "robot_agent/slam/seen_robot_mask.h"

namespace fleetmap {

// One run: every robot's local SLAM (and the mask of the robots it saw) fed by the simulator,
// a MergeEngine fed as the run goes, and what the truth says of each robot's frames.
class SimRun {
 public:
  SimRun(std::unique_ptr<sim::Simulation> sim, const BenchOptions& options, RunResult* result)
      : sim_(std::move(sim)),
        options_(options),
        result_(result),
        infos_(sim_->robots()),
        n_(infos_.size()),
        masks_(n_),
        latest_truth_(n_),
        detection_noise_(0.0, options.detection_sigma),
        engine_(options.engine),
        next_feed_(options.feed_period) {}

  // One local SLAM per robot, as the bench options choose it.
  bool Start(std::string* error);
  // The simulation to its end; the engine is fed every feed_period of simulated time.
  void Drive();
  // Each robot's local SLAM drift: the final pose against the truth, through the start.
  void ReportLocalSlam();
  // The merge (or its settled rebuild) scored against the truth.
  bool Score(std::string* error);

 private:
  void OnLaser(sim::SensorPacket& packet);
  void OnVisibility(const std::vector<sim::VisibilityRecord>& visibility, double timestamp);
  // The robots' new submaps, trajectories and detections into the engine, then Update().
  void Feed(bool last);
  void PrintEvents(const MergeUpdate& update) const;
  // Notes the pairs the merge as fed now places beyond the false-merge thresholds.
  void NoteFalseJoins();
  // Those pairs, when and how far off, as one report line.
  std::string FalseJoinsLine() const;
  // Uploads settled: what the engine as fed holds on probation judged on the maps as they are.
  void SettleAsFed();
  // As the server's worker rebuilds from its store once uploads settle.
  void RebuildAsSettled(MergeEngine* rebuilt) const;

  std::unique_ptr<sim::Simulation> sim_;
  const BenchOptions& options_;
  RunResult* result_;
  const std::vector<sim::SimRobotInfo>& infos_;
  const size_t n_;
  std::vector<std::unique_ptr<LocalSlam>> slams_;
  RunTruth truth_;
  std::map<std::string, size_t> index_;
  // As in the agent: each robot masks the returns off robots its camera saw (every visible
  // record, the camera's rate), whatever the upload period of the detections.
  std::vector<SeenRobotMask> masks_;
  std::vector<Rigid2d> latest_truth_;
  std::map<std::pair<int, int>, double> last_detection_;
  std::mt19937 detection_rng_{7};
  std::normal_distribution<double> detection_noise_;
  std::mt19937 outlier_rng_{11};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  MergeEngine engine_;
  std::vector<double> update_ms_, fold_ms_;
  double next_feed_;
  std::vector<RobotDetection> pending_detections_;
  std::map<NodeId, Submap> latest_submaps_;  // as the engine has them, for ScoreMapBounds
  std::vector<NodeId> arrival_;              // first arrival order, for a rebuild
  std::vector<RobotDetection> all_detections_;
  // Per robot pair (PairErrors' order): when the merge as fed first placed it beyond the
  // false-merge thresholds (simulated seconds), how far off, and when it last stopped being so
  // (none while it is).
  struct FalseJoin {
    double from = 0.0;
    Rigid2d off;
    std::optional<double> until;
  };
  std::map<size_t, FalseJoin> false_as_fed_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_BENCH_SIM_RUN_H_
