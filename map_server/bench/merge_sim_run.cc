// fleetmap-merge-sim-bench's run: simulator -> local SLAM -> MergeEngine, scored against the truth.

#include "map_server/bench/merge_sim_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>

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

}  // namespace

bool Run(const std::string& scenario, const BenchOptions& options, RunResult* result,
         std::string* error) {
  std::unique_ptr<sim::Simulation> sim = LoadSimulation(scenario, options.seed_offset, error);
  if (!sim) {
    *error = scenario + ": " + *error;
    return false;
  }
  const auto& infos = sim->robots();
  const size_t n = infos.size();
  std::vector<std::unique_ptr<LocalSlam>> slams;
  for (const auto& info : infos) {
    BackendChoice choice;
    choice.robot_id = info.name;
    choice.algorithm = options.algorithm;
    choice.submap_scans = options.submap_scans;
    choice.submap_travel = options.submap_travel;
    slams.push_back(MakeLocalSlam(choice, error));
    if (!slams.back()) return false;
  }
  RunTruth run_truth;
  for (const auto& info : infos) run_truth.names.push_back(info.name);
  run_truth.local_in_world.resize(n);
  run_truth.first_submap_in_local.resize(n);
  run_truth.at_scan.resize(n);
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < n; ++i) index[infos[i].name] = i;
  std::map<std::pair<int, int>, double> last_detection;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, options.detection_sigma);
  std::mt19937 outlier_rng(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  MergeEngine engine(options.engine);
  std::vector<double> update_ms, fold_ms;
  double next_feed = options.feed_period;
  std::vector<RobotDetection> pending_detections;
  std::map<NodeId, Submap> latest_submaps;  // as the engine has them, for ScoreMapBounds
  std::vector<NodeId> arrival;              // first arrival order, for a rebuild
  std::vector<RobotDetection> all_detections;
  const auto feed = [&](bool last) {
    int new_submaps = 0;
    for (size_t i = 0; i < n; ++i) {
      if (last) slams[i]->Finish();
      for (const Submap& submap : slams[i]->TakeSubmapUpdates()) {
        new_submaps += submap.finished;
        if (submap.submap_id == 0) run_truth.first_submap_in_local[i] = submap.submap_in_local;
        if (!submap.scan_poses.empty()) {
          run_truth.anchors[NodeId{infos[i].name, submap.submap_id}] = {
              submap.scan_poses.front().pose.inverse() * submap.submap_in_local,
              submap.scan_poses.front().timestamp};
        }
        const NodeId id{infos[i].name, submap.submap_id};
        if (!latest_submaps.count(id)) arrival.push_back(id);
        latest_submaps[id] = submap;
        engine.AddOrUpdateSubmap(submap);
      }
      engine.SetTrajectory(infos[i].name, slams[i]->trajectory());
    }
    for (const RobotDetection& d : pending_detections) engine.AddDetection(d);
    all_detections.insert(all_detections.end(), pending_detections.begin(),
                          pending_detections.end());
    pending_detections.clear();
    result->submaps += new_submaps;
    const auto print_events = [&](const MergeUpdate& update) {
      if (!options.verbose) return;
      for (const AlignmentEvent& e : update.events) {
        // How far the evidence's estimate is from the truth (start frames; includes drift).
        std::string truth_error;
        const auto a = index.find(e.robot_a), b = index.find(e.robot_b);
        if (e.local_b_in_local_a && a != index.end() && b != index.end() &&
            run_truth.local_in_world[a->second] && run_truth.local_in_world[b->second]) {
          const Rigid2d diff = (run_truth.local_in_world[a->second]->inverse() *
                                *run_truth.local_in_world[b->second])
                                   .inverse() *
                               *e.local_b_in_local_a;
          char text[80];
          std::snprintf(text, sizeof(text), " [vs truth %.2f m, %.2f deg]",
                        diff.translation().norm(),
                        std::abs(NormalizeAngle(diff.rotation())) * 180.0 / M_PI);
          truth_error = text;
        }
        std::printf("    t=%.0f %s %s/%s score %.3f amb %.3f overlap %.3f%s: %s\n",
                    result->sim_seconds, AlignmentEventTypeName(e.type), e.robot_a.c_str(),
                    e.robot_b.c_str(), e.score, e.ambiguity, e.overlap, truth_error.c_str(),
                    e.reason.c_str());
      }
    };
    const auto start = std::chrono::steady_clock::now();
    const MergeUpdate update = engine.Update();
    print_events(update);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    update_ms.push_back(ms);
    if (new_submaps > 0) fold_ms.push_back(ms / new_submaps);
    // Postponed searches, as the server's worker runs them while idle.
    for (int i = 0; i < 1000 && engine.HasPendingWork(); ++i) print_events(engine.Update());
  };
  // As in the agent: each robot masks the returns off robots its camera saw (every visible
  // record, the camera's rate), whatever the upload period of the detections.
  std::vector<SeenRobotMask> masks(n);
  std::vector<Rigid2d> latest_truth(n);
  const double body_radius = sim->scenario().body.radius;
  while (!sim->Done()) {
    sim::StepResult step = sim->Step();
    for (sim::SensorPacket& packet : step.packets) {
      const size_t i = static_cast<size_t>(packet.robot_index);
      LocalSlam& slam = *slams[i];
      std::string why;
      if (packet.laser) {
        // As in the agent (MappingPipeline) and fleetmap-slam: odometry comes from the laser's
        // records, one reading at each scan's instant. The simulator's odometry records run at
        // their own rate (every 0.06 s against the laser's 0.1 s); fed from them, a scan between
        // two readings, along a plain corridor where the match keeps odometry's translation,
        // was placed centimetres off.
        slam.AddOdometry({packet.laser->scan.timestamp, packet.laser->robot_pose}, &why);
        masks[i].AddOdometry(packet.laser->scan.timestamp, packet.laser->robot_pose);
        if (!run_truth.local_in_world[i]) run_truth.local_in_world[i] = packet.ground_truth;
        run_truth.at_scan[i][packet.laser->scan.timestamp] = packet.ground_truth;
        latest_truth[i] = packet.ground_truth;
        if (options.mask_laser_bodies) {
          const std::vector<Eigen::Vector2d> bodies =
              FindLaserBodies(packet.laser->scan, body_radius, options.laser_bodies);
          for (const Eigen::Vector2d& body : bodies) {
            ++result->laser_bodies;
            bool on_robot = false;
            for (size_t j = 0; j < n && !on_robot; ++j) {
              on_robot =
                  j != i &&
                  (latest_truth[i].inverse() * latest_truth[j].translation() - body).norm() < 0.3;
            }
            result->laser_bodies_on_robots += on_robot;
          }
          masks[i].AddLaserBodies(packet.laser->scan.timestamp, bodies);
        }
        if ((options.detections && options.mask_seen_robots) || options.mask_laser_bodies) {
          result->masked_returns += masks[i].Apply(&packet.laser->scan);
        }
        slam.AddScan(packet.laser->scan, &why);
      }
    }
    if (options.detections) {
      for (const sim::VisibilityRecord& v : step.visibility) {
        if (!v.visible || !run_truth.local_in_world[v.observer] ||
            !run_truth.local_in_world[v.observed]) {
          continue;
        }
        RobotDetection seen;
        seen.observer_id = infos[v.observer].name;
        seen.observed_id = infos[v.observed].name;
        seen.timestamp = step.timestamp;
        seen.position_in_observer = v.relative.translation();
        masks[v.observer].AddDetection(seen);
        double& last = last_detection[{v.observer, v.observed}];
        if (last > 0.0 && step.timestamp - last < options.detection_period) continue;
        last = step.timestamp;
        RobotDetection d;
        d.observer_id = infos[v.observer].name;
        d.observed_id = infos[v.observed].name;
        d.timestamp = step.timestamp;
        d.position_in_observer = v.relative.translation() + Eigen::Vector2d(noise(rng), noise(rng));
        if (uniform(outlier_rng) < options.outlier_fraction) {
          const double angle = 2.0 * M_PI * uniform(outlier_rng),
                       distance = 1.0 + 4.0 * uniform(outlier_rng);
          d.position_in_observer += distance * Eigen::Vector2d(std::cos(angle), std::sin(angle));
        }
        d.covariance =
            Eigen::Matrix2d::Identity() * options.detection_sigma * options.detection_sigma;
        pending_detections.push_back(d);
      }
    }
    if (step.timestamp >= next_feed) {
      next_feed += options.feed_period;
      feed(false);
    }
    result->sim_seconds = step.timestamp;
  }
  feed(true);
  // Local SLAM drift: the final pose against the truth, through the start.
  for (size_t i = 0; i < n; ++i) {
    const Trajectory& t = slams[i]->trajectory();
    if (t.empty() || !run_truth.local_in_world[i]) continue;
    const Rigid2d end = *run_truth.local_in_world[i] * t.back().pose;
    const Rigid2d truth = sim->TruePoses()[i];
    char line[200];
    std::snprintf(line, sizeof(line),
                  "  %s local SLAM end-pose error %.3f m, %.2f deg (first pose %.3f %.3f %.3f)",
                  infos[i].name.c_str(), (end.translation() - truth.translation()).norm(),
                  std::abs(NormalizeAngle(end.rotation() - truth.rotation())) * 180.0 / M_PI,
                  t.front().pose.translation().x(), t.front().pose.translation().y(),
                  t.front().pose.rotation());
    result->lines.push_back(line);
    result->lines.push_back(HeadingErrorSummary(t, run_truth, i));
  }
  MergeEngine rebuilt(options.engine);
  if (options.settled_rebuild) {
    // As the server's worker rebuilds from its store: submaps in arrival order, then the
    // trajectories and the detections, then Update() until nothing is postponed.
    for (const NodeId& id : arrival) rebuilt.AddOrUpdateSubmap(latest_submaps.at(id));
    for (size_t i = 0; i < n; ++i) rebuilt.SetTrajectory(infos[i].name, slams[i]->trajectory());
    for (const RobotDetection& d : all_detections) rebuilt.AddDetection(d);
    for (int i = 0; i == 0 || (i < 10000 && rebuilt.HasPendingWork()); ++i) rebuilt.Update();
  }
  // The server keeps the rebuild only when it places at least as many robots.
  const bool rebuild_kept =
      options.settled_rebuild && rebuilt.PlacedRobots().size() >= engine.PlacedRobots().size();
  if (options.settled_rebuild) {
    char line[160];
    std::snprintf(line, sizeof(line),
                  "  settled rebuild: %zu robots placed (the engine fed as the run went: %zu): %s",
                  rebuilt.PlacedRobots().size(), engine.PlacedRobots().size(),
                  rebuild_kept ? "kept" : "not kept");
    result->lines.push_back(line);
  }
  const MergeEngine& scored = rebuild_kept ? rebuilt : engine;
  if (options.settled_rebuild) {
    // Both merges against the truth and by the engine's own consistency figure: whether the
    // engine could tell which of the two is better.
    RunResult as_fed, whole;
    std::string ignored;
    ScoreMerge(engine, run_truth, sim->world(), options.false_translation, options.false_rotation,
               &as_fed, &ignored);
    ScoreMerge(rebuilt, run_truth, sim->world(), options.false_translation, options.false_rotation,
               &whole, &ignored);
    char line[200];
    std::snprintf(line, sizeof(line),
                  "  as fed: map %.2f %%, disagreement %.5f; rebuilt: map %.2f %%, disagreement "
                  "%.5f",
                  100.0 * as_fed.map_accuracy, engine.Quality().disagreement_fraction(),
                  100.0 * whole.map_accuracy, rebuilt.Quality().disagreement_fraction());
    result->lines.push_back(line);
  }
  ScoreMerge(scored, run_truth, sim->world(), options.false_translation, options.false_rotation,
             result, error);
  ScoreMapBounds(latest_submaps, run_truth, sim->world(), result);
  if (options.diagnose) PrintSubmapDiagnosis(scored, latest_submaps, run_truth);
  result->median_update_ms = Median(update_ms);
  result->max_update_ms =
      update_ms.empty() ? 0.0 : *std::max_element(update_ms.begin(), update_ms.end());
  result->median_fold_ms = Median(fold_ms);
  return true;
}

}  // namespace fleetmap
