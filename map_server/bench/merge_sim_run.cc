// fleetmap-merge-sim-bench's run: simulator -> local SLAM -> MergeEngine, scored against the truth.

#include "map_server/bench/merge_sim_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <random>

#include "map_server/bench/merge_sim_diagnosis.h"
#include "map_server/bench/merge_sim_report.h"
#include "map_server/bench/merge_sim_scoring.h"
#include "map_server/merge/merge_engine.h"
#include "robot_agent/detection/laser_body.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/simulation.h"
#include "robot_agent/sim/world_io.h"
#include "robot_agent/slam/backend_factory.h"
#include "robot_agent/slam/seen_robot_mask.h"

namespace fleetmap {
namespace {

std::unique_ptr<sim::Simulation> LoadSimulation(const std::string& path, uint64_t seed_offset,
                                                std::string* error) {
  sim::Scenario scenario;
  if (!sim::LoadScenario(path, &scenario, error)) return nullptr;
  scenario.camera.enabled = false;
  scenario.seed += seed_offset;
  sim::World world;
  if (!sim::LoadWorld(scenario.world_path, &world, error)) return nullptr;
  return sim::Simulation::Create(scenario, std::move(world), error);
}

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

bool SimRun::Start(std::string* error) {
  for (const auto& info : infos_) {
    BackendChoice choice;
    choice.robot_id = info.name;
    choice.algorithm = options_.algorithm;
    choice.submap_scans = options_.submap_scans;
    choice.submap_travel = options_.submap_travel;
    choice.submap_resolution = options_.submap_resolution;
    slams_.push_back(MakeLocalSlam(choice, error));
    if (!slams_.back()) return false;
  }
  for (const auto& info : infos_) truth_.names.push_back(info.name);
  truth_.local_in_world.resize(n_);
  truth_.first_submap_in_local.resize(n_);
  truth_.at_scan.resize(n_);
  for (size_t i = 0; i < n_; ++i) index_[infos_[i].name] = i;
  return true;
}

void SimRun::Drive() {
  while (!sim_->Done()) {
    sim::StepResult step = sim_->Step();
    for (sim::SensorPacket& packet : step.packets) {
      if (packet.laser) OnLaser(packet);
    }
    if (options_.detections) OnVisibility(step.visibility, step.timestamp);
    if (step.timestamp >= next_feed_) {
      next_feed_ += options_.feed_period;
      Feed(false);
    }
    result_->sim_seconds = step.timestamp;
  }
  Feed(true);
}

void SimRun::OnLaser(sim::SensorPacket& packet) {
  const size_t i = static_cast<size_t>(packet.robot_index);
  std::string why;
  // As in the agent (MappingPipeline) and fleetmap-slam: odometry comes from the laser's
  // records, one reading at each scan's instant. The simulator's odometry records run at
  // their own rate (every 0.06 s against the laser's 0.1 s); fed from them, a scan between
  // two readings, along a plain corridor where the match keeps odometry's translation,
  // was placed centimetres off.
  slams_[i]->AddOdometry({packet.laser->scan.timestamp, packet.laser->robot_pose}, &why);
  masks_[i].AddOdometry(packet.laser->scan.timestamp, packet.laser->robot_pose);
  if (!truth_.local_in_world[i]) truth_.local_in_world[i] = packet.ground_truth;
  truth_.at_scan[i][packet.laser->scan.timestamp] = packet.ground_truth;
  latest_truth_[i] = packet.ground_truth;
  if (options_.mask_laser_bodies) {
    const double body_radius = sim_->scenario().body.radius;
    const std::vector<Eigen::Vector2d> bodies =
        FindLaserBodies(packet.laser->scan, body_radius, options_.laser_bodies);
    for (const Eigen::Vector2d& body : bodies) {
      ++result_->laser_bodies;
      bool on_robot = false;
      for (size_t j = 0; j < n_ && !on_robot; ++j) {
        on_robot =
            j != i &&
            (latest_truth_[i].inverse() * latest_truth_[j].translation() - body).norm() < 0.3;
      }
      result_->laser_bodies_on_robots += on_robot;
    }
    masks_[i].AddLaserBodies(packet.laser->scan.timestamp, bodies);
  }
  if ((options_.detections && options_.mask_seen_robots) || options_.mask_laser_bodies) {
    result_->masked_returns += masks_[i].Apply(&packet.laser->scan);
  }
  slams_[i]->AddScan(packet.laser->scan, &why);
}

void SimRun::OnVisibility(const std::vector<sim::VisibilityRecord>& visibility, double timestamp) {
  for (const sim::VisibilityRecord& v : visibility) {
    if (!v.visible || !truth_.local_in_world[v.observer] || !truth_.local_in_world[v.observed]) {
      continue;
    }
    RobotDetection seen;
    seen.observer_id = infos_[v.observer].name;
    seen.observed_id = infos_[v.observed].name;
    seen.timestamp = timestamp;
    seen.position_in_observer = v.relative.translation();
    masks_[v.observer].AddDetection(seen);
    double& last = last_detection_[{v.observer, v.observed}];
    if (last > 0.0 && timestamp - last < options_.detection_period) continue;
    last = timestamp;
    RobotDetection d = seen;
    d.position_in_observer +=
        Eigen::Vector2d(detection_noise_(detection_rng_), detection_noise_(detection_rng_));
    if (uniform_(outlier_rng_) < options_.outlier_fraction) {
      const double angle = 2.0 * M_PI * uniform_(outlier_rng_),
                   distance = 1.0 + 4.0 * uniform_(outlier_rng_);
      d.position_in_observer += distance * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    d.covariance =
        Eigen::Matrix2d::Identity() * options_.detection_sigma * options_.detection_sigma;
    pending_detections_.push_back(d);
  }
}

void SimRun::Feed(bool last) {
  int new_submaps = 0;
  for (size_t i = 0; i < n_; ++i) {
    if (last) slams_[i]->Finish();
    for (const Submap& submap : slams_[i]->TakeSubmapUpdates()) {
      new_submaps += submap.finished;
      if (submap.submap_id == 0) truth_.first_submap_in_local[i] = submap.submap_in_local;
      if (!submap.scan_poses.empty()) {
        truth_.anchors[NodeId{infos_[i].name, submap.submap_id}] = {
            submap.scan_poses.front().pose.inverse() * submap.submap_in_local,
            submap.scan_poses.front().timestamp};
      }
      const NodeId id{infos_[i].name, submap.submap_id};
      if (!latest_submaps_.count(id)) arrival_.push_back(id);
      latest_submaps_[id] = submap;
      engine_.AddOrUpdateSubmap(submap);
    }
    engine_.SetTrajectory(infos_[i].name, slams_[i]->trajectory());
  }
  for (const RobotDetection& d : pending_detections_) engine_.AddDetection(d);
  all_detections_.insert(all_detections_.end(), pending_detections_.begin(),
                         pending_detections_.end());
  pending_detections_.clear();
  result_->submaps += new_submaps;
  const auto start = std::chrono::steady_clock::now();
  const MergeUpdate update = engine_.Update();
  PrintEvents(update);
  NoteFalseJoins();
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  update_ms_.push_back(ms);
  if (new_submaps > 0) fold_ms_.push_back(ms / new_submaps);
  // Postponed searches, as the server's worker runs them while idle.
  for (int i = 0; i < 1000 && engine_.HasPendingWork(); ++i) {
    PrintEvents(engine_.Update());
    NoteFalseJoins();
  }
}

void SimRun::NoteFalseJoins() {
  const std::vector<std::optional<Rigid2d>> errors = PairErrors(engine_, truth_);
  for (size_t k = 0; k < errors.size(); ++k) {
    const bool wrong =
        errors[k] && IsFalseMerge(*errors[k], options_.false_translation, options_.false_rotation);
    const auto it = false_as_fed_.find(k);
    if (wrong && it == false_as_fed_.end()) {
      false_as_fed_.emplace(k, FalseJoin{result_->sim_seconds, *errors[k], std::nullopt});
    } else if (wrong) {
      it->second.until.reset();
    } else if (it != false_as_fed_.end() && !it->second.until) {
      it->second.until = result_->sim_seconds;
    }
  }
}

void SimRun::PrintEvents(const MergeUpdate& update) const {
  if (!options_.verbose) return;
  for (const AlignmentEvent& e : update.events) {
    // How far the evidence's estimate is from the truth (start frames; includes drift).
    std::string truth_error;
    const auto a = index_.find(e.robot_a), b = index_.find(e.robot_b);
    if (e.local_b_in_local_a && a != index_.end() && b != index_.end() &&
        truth_.local_in_world[a->second] && truth_.local_in_world[b->second]) {
      const Rigid2d diff =
          (truth_.local_in_world[a->second]->inverse() * *truth_.local_in_world[b->second])
              .inverse() *
          *e.local_b_in_local_a;
      char text[80];
      std::snprintf(text, sizeof(text), " [vs truth %.2f m, %.2f deg]", diff.translation().norm(),
                    std::abs(NormalizeAngle(diff.rotation())) * 180.0 / M_PI);
      truth_error = text;
    }
    std::printf("    t=%.0f %s %s/%s score %.3f amb %.3f overlap %.3f%s: %s\n",
                result_->sim_seconds, AlignmentEventTypeName(e.type), e.robot_a.c_str(),
                e.robot_b.c_str(), e.score, e.ambiguity, e.overlap, truth_error.c_str(),
                e.reason.c_str());
  }
}

void SimRun::ReportLocalSlam() {
  for (size_t i = 0; i < n_; ++i) {
    const Trajectory& t = slams_[i]->trajectory();
    if (t.empty() || !truth_.local_in_world[i]) continue;
    const Rigid2d end = *truth_.local_in_world[i] * t.back().pose;
    const Rigid2d truth = sim_->TruePoses()[i];
    char line[200];
    std::snprintf(line, sizeof(line),
                  "  %s local SLAM end-pose error %.3f m, %.2f deg (first pose %.3f %.3f %.3f)",
                  infos_[i].name.c_str(), (end.translation() - truth.translation()).norm(),
                  std::abs(NormalizeAngle(end.rotation() - truth.rotation())) * 180.0 / M_PI,
                  t.front().pose.translation().x(), t.front().pose.translation().y(),
                  t.front().pose.rotation());
    result_->lines.push_back(line);
    result_->lines.push_back(HeadingErrorSummary(t, truth_, i));
  }
}

void SimRun::RebuildAsSettled(MergeEngine* rebuilt) const {
  // Submaps in arrival order, then the trajectories and the detections, then Update() until
  // nothing is postponed. All at once, as the server's rebuild does: no probation.
  rebuilt->HoldMatchOnlyJoins(false);
  for (const NodeId& id : arrival_) rebuilt->AddOrUpdateSubmap(latest_submaps_.at(id));
  for (size_t i = 0; i < n_; ++i) rebuilt->SetTrajectory(infos_[i].name, slams_[i]->trajectory());
  for (const RobotDetection& d : all_detections_) rebuilt->AddDetection(d);
  for (int i = 0; i == 0 || (i < 10000 && rebuilt->HasPendingWork()); ++i) rebuilt->Update();
}

void SimRun::SettleAsFed() {
  // As the server's worker does once uploads settle: joins held on probation judged now.
  const size_t placed = engine_.PlacedRobots().size();
  engine_.HoldMatchOnlyJoins(false);
  for (int i = 0; i < 1000 && engine_.HasPendingWork(); ++i) {
    PrintEvents(engine_.Update());
    NoteFalseJoins();
  }
  char line[160];
  std::snprintf(line, sizeof(line),
                "  uploads settled: the engine as fed placed %zu robots, %zu once what it held on "
                "probation was judged",
                placed, engine_.PlacedRobots().size());
  result_->lines.push_back(line);
}

bool SimRun::Score(std::string* error) {
  MergeEngine rebuilt(options_.engine);
  if (options_.settled_rebuild) {
    SettleAsFed();
    RebuildAsSettled(&rebuilt);
  }
  // The server keeps the rebuild only when it places at least as many robots.
  const bool rebuild_kept =
      options_.settled_rebuild && rebuilt.PlacedRobots().size() >= engine_.PlacedRobots().size();
  const sim::World& world = sim_->world();
  if (options_.settled_rebuild) {
    char line[200];
    std::snprintf(line, sizeof(line),
                  "  settled rebuild: %zu robots placed (the engine fed as the run went: %zu): %s",
                  rebuilt.PlacedRobots().size(), engine_.PlacedRobots().size(),
                  rebuild_kept ? "kept" : "not kept");
    result_->lines.push_back(line);
    // Both merges against the truth and by the engine's own consistency figure: whether the
    // engine could tell which of the two is better.
    RunResult as_fed, whole;
    std::string ignored;
    ScoreMerge(engine_, truth_, world, options_.false_translation, options_.false_rotation, &as_fed,
               &ignored);
    ScoreMerge(rebuilt, truth_, world, options_.false_translation, options_.false_rotation, &whole,
               &ignored);
    std::snprintf(
        line, sizeof(line),
        "  as fed: map %.2f %%, disagreement %.5f; rebuilt: map %.2f %%, disagreement %.5f",
        100.0 * as_fed.map_accuracy, engine_.Quality().disagreement_fraction(),
        100.0 * whole.map_accuracy, rebuilt.Quality().disagreement_fraction());
    result_->lines.push_back(line);
  }
  result_->false_merges_as_fed = static_cast<int>(false_as_fed_.size());
  {
    std::string line = "  false joins as the run went: " + std::to_string(false_as_fed_.size());
    size_t k = 0;
    for (size_t a = 0; a < n_; ++a) {
      for (size_t b = a + 1; b < n_; ++b, ++k) {
        const auto it = false_as_fed_.find(k);
        if (it == false_as_fed_.end()) continue;
        const FalseJoin& f = it->second;
        char until[40] = "to the end";
        if (f.until) std::snprintf(until, sizeof(until), "until t=%.0f s", *f.until);
        char text[200];
        std::snprintf(text, sizeof(text), "; %s-%s from t=%.0f s %s (%.2f m, %.1f deg off)",
                      infos_[a].name.c_str(), infos_[b].name.c_str(), f.from, until,
                      f.off.translation().norm(),
                      std::abs(NormalizeAngle(f.off.rotation())) * 180.0 / M_PI);
        line += text;
      }
    }
    result_->lines.push_back(line);
  }
  const MergeEngine& scored = rebuild_kept ? rebuilt : engine_;
  ScoreMerge(scored, truth_, world, options_.false_translation, options_.false_rotation, result_,
             error);
  ScoreMapBounds(latest_submaps_, truth_, world, result_);
  if (options_.diagnose)
    PrintSubmapDiagnosis(scored, latest_submaps_, truth_, options_.engine, world);
  result_->median_update_ms = Median(update_ms_);
  result_->max_update_ms =
      update_ms_.empty() ? 0.0 : *std::max_element(update_ms_.begin(), update_ms_.end());
  result_->median_fold_ms = Median(fold_ms_);
  return true;
}

}  // namespace

bool Run(const std::string& scenario, const BenchOptions& options, RunResult* result,
         std::string* error) {
  std::unique_ptr<sim::Simulation> sim = LoadSimulation(scenario, options.seed_offset, error);
  if (!sim) {
    *error = scenario + ": " + *error;
    return false;
  }
  SimRun run(std::move(sim), options, result);
  if (!run.Start(error)) return false;
  run.Drive();
  run.ReportLocalSlam();
  return run.Score(error);
}

}  // namespace fleetmap
