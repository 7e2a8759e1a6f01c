// Merge benchmark: robots with unknown start frames tour a synthetic building; their submaps,
// trajectories and detections (some corrupted) stream into a MergeEngine, one Update() per new
// submap. Prints alignment errors against ground truth, false merges, map accuracy and the time
// to fold one submap in.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <random>

#include <CLI/CLI.hpp>

#include "map_server/merge/bench/synthetic_building.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap::bench {
namespace {

struct Config {
  int robots = 4;
  int submaps_per_robot = 100;
  int scans_per_submap = 10;
  int rooms_x = 4;
  int rooms_y = 3;
  unsigned seed = 1;
  bool detections = true;
  bool local_constraints = true;
  bool diagnose = false;
  double outlier_fraction = 0.1;
  double detection_sigma = 0.02;
  double detection_period = 4.0;  // seconds between detection attempts
  double dt = 0.5;                // seconds between scans
  double step = 0.25;             // metres between scans
  double whole_map_ambiguity = MergeEngineOptions().whole_map_ambiguity;
  int whole_map_min_contradictions = MergeEngineOptions().whole_map_min_contradictions;
  bool whole_map_rule_out_higher = MergeEngineOptions().whole_map_rule_out_higher;
  double cross_retry_growth = MergeEngineOptions().cross_retry_growth;
  double edge_refine_window = MergeEngineOptions().edge_refine_window;
  int search_threads = MergeEngineOptions().search_threads;
  bool verbose = false;
};

struct SimRobot {
  std::string id;
  std::vector<Rigid2d> path;
  Rigid2d local_in_world;
  Trajectory trajectory;  // in the local frame
};

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

Submap MakeSubmap(const Building& b, const SimRobot& r, int k, int scans) {
  Submap s;
  s.robot_id = r.id;
  s.submap_id = k;
  s.revision = 1;
  s.finished = true;
  const size_t first = static_cast<size_t>(k) * static_cast<size_t>(scans);
  s.submap_in_local = r.trajectory[first].pose;
  const Rigid2d local_in_submap = s.submap_in_local.inverse();
  for (size_t i = first; i < first + static_cast<size_t>(scans); ++i) {
    s.scan_poses.push_back(r.trajectory[i]);
    s.grid.InsertScan(Scan(b, r.path[i], r.trajectory[i].timestamp), local_in_submap * r.trajectory[i].pose);
  }
  return s;
}

bool LineOfSight(const Building& b, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const Eigen::Vector2d d = to - from;
  return CastRay(b, from, std::atan2(d.y(), d.x()), 100.0) > d.norm() - 0.05;
}

int Run(const Config& c) {
  std::mt19937 rng(c.seed);
  const Building building = MakeBuilding(c.rooms_x, c.rooms_y, &rng);
  const int steps = c.submaps_per_robot * c.scans_per_submap;
  std::uniform_real_distribution<double> heading(-M_PI, M_PI), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<SimRobot> robots;
  for (int r = 0; r < c.robots; ++r) {
    SimRobot robot;
    robot.id = "robot" + std::to_string(r);
    robot.path = RandomTour(building, steps, c.step, &rng);
    // Unknown start: the local frame sits at the start position with a random heading.
    robot.local_in_world = Rigid2d(robot.path.front().translation(), heading(rng));
    for (int i = 0; i < steps; ++i) {
      robot.trajectory.push_back({i * c.dt, robot.local_in_world.inverse() * robot.path[static_cast<size_t>(i)]});
    }
    robots.push_back(std::move(robot));
  }
  const auto find = [&](const std::string& id) -> const SimRobot& {
    for (const SimRobot& r : robots) {
      if (r.id == id) return r;
    }
    return robots.front();
  };

  MergeEngineOptions options;
  options.local_constraints = c.local_constraints;
  options.whole_map_ambiguity = c.whole_map_ambiguity;
  options.whole_map_min_contradictions = c.whole_map_min_contradictions;
  options.whole_map_rule_out_higher = c.whole_map_rule_out_higher;
  options.cross_retry_growth = c.cross_retry_growth;
  options.edge_refine_window = c.edge_refine_window;
  options.search_threads = c.search_threads;
  MergeEngine engine(options);
  std::vector<bool> corrupted;
  int detections_total = 0, next_detection_step = 0;
  const int detection_stride = std::max(1, static_cast<int>(c.detection_period / c.dt));
  std::vector<double> update_ms, late_update_ms, placed_update_ms;
  int false_merges = 0, accepted_alignments = 0, corrupted_used = 0, corrupted_rejected = 0;
  double worst_accept_t = 0.0, worst_accept_r = 0.0;
  size_t nodes = 0;
  for (int k = 0; k < c.submaps_per_robot; ++k) {
    for (SimRobot& robot : robots) {
      const int end_step = (k + 1) * c.scans_per_submap;  // exclusive
      std::string error;
      if (!engine.AddOrUpdateSubmap(MakeSubmap(building, robot, k, c.scans_per_submap), &error) ||
          !engine.SetTrajectory(robot.id, Trajectory(robot.trajectory.begin(), robot.trajectory.begin() + end_step), &error)) {
        std::cerr << "error: " << error << "\n";
        return 1;
      }
      ++nodes;
      // Detections up to the time every robot has reached.
      const int reached = k * c.scans_per_submap + (&robot == &robots.back() ? c.scans_per_submap : 0);
      while (c.detections && next_detection_step < reached) {
        const size_t i = static_cast<size_t>(next_detection_step);
        for (const SimRobot& o : robots) {
          for (const SimRobot& s : robots) {
            if (&o == &s) continue;
            const Rigid2d rel = o.path[i].inverse() * s.path[i];
            if (rel.translation().norm() > 6.0 || !LineOfSight(building, o.path[i].translation(), s.path[i].translation())) continue;
            RobotDetection d;
            d.observer_id = o.id;
            d.observed_id = s.id;
            d.timestamp = static_cast<double>(i) * c.dt;
            d.position_in_observer = rel.translation() + c.detection_sigma * Eigen::Vector2d(noise(rng), noise(rng));
            d.covariance = Eigen::Matrix2d::Identity() * c.detection_sigma * c.detection_sigma;
            if (unit(rng) < 0.5) {
              d.relative_heading = rel.rotation() + 0.01 * noise(rng);
              d.relative_heading_variance = 0.01 * 0.01;
            }
            const bool bad = unit(rng) < c.outlier_fraction;
            if (bad) {
              const double a = heading(rng), m = 1.0 + 2.0 * unit(rng);
              d.position_in_observer += m * Eigen::Vector2d(std::cos(a), std::sin(a));
              if (d.relative_heading) *d.relative_heading += heading(rng);
            }
            if (engine.AddDetection(d)) {
              corrupted.push_back(bad);
              ++detections_total;
            }
          }
        }
        next_detection_step += detection_stride;
      }
      const auto start = std::chrono::steady_clock::now();
      const MergeUpdate update = engine.Update();
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      update_ms.push_back(ms);
      if (nodes + 40 > static_cast<size_t>(c.robots * c.submaps_per_robot)) late_update_ms.push_back(ms);
      if (static_cast<int>(update.placed_robots.size()) == c.robots) placed_update_ms.push_back(ms);
      for (const AlignmentEvent& e : update.events) {
        if (c.verbose && e.type != AlignmentEventType::kPending) {
          std::printf("    submap %d: %s %s/%s: %s\n", k, AlignmentEventTypeName(e.type),
                      e.robot_a.c_str(), e.robot_b.c_str(), e.reason.c_str());
        }
        const bool bad = e.detection_index && corrupted[*e.detection_index];
        if (bad && (e.type == AlignmentEventType::kAlignmentAccepted || e.type == AlignmentEventType::kConstraintAdded)) ++corrupted_used;
        if (bad && e.type == AlignmentEventType::kRejected) ++corrupted_rejected;
        if (e.type != AlignmentEventType::kAlignmentAccepted || !e.local_b_in_local_a) continue;
        ++accepted_alignments;
        const Rigid2d truth = find(e.robot_a).local_in_world.inverse() * find(e.robot_b).local_in_world;
        const Rigid2d err = truth.inverse() * *e.local_b_in_local_a;
        worst_accept_t = std::max(worst_accept_t, err.translation().norm());
        worst_accept_r = std::max(worst_accept_r, std::abs(err.rotation()));
        if (err.translation().norm() > 0.3 || std::abs(err.rotation()) > 3.0 * M_PI / 180) ++false_merges;
        std::printf("  accepted %s <- %s (%s) error %.3f m %.3f deg at submap %d\n", e.robot_a.c_str(), e.robot_b.c_str(),
                    e.detection_index ? "detection" : "cross match", err.translation().norm(),
                    std::abs(err.rotation()) * 180 / M_PI, k);
      }
    }
    if ((k + 1) % 10 == 0) {
      std::printf("submaps %zu, placed robots %zu, last update %.1f ms\n", nodes, engine.PlacedRobots().size(), update_ms.back());
      std::fflush(stdout);
    }
  }

  // Final relative transforms against ground truth.
  double worst_t = 0.0, worst_r = 0.0;
  int pairs = 0;
  for (size_t a = 0; a < robots.size(); ++a) {
    for (size_t b = a + 1; b < robots.size(); ++b) {
      const auto ga = engine.RobotToGlobal(robots[a].id), gb = engine.RobotToGlobal(robots[b].id);
      if (!ga || !gb) continue;
      const Rigid2d truth = robots[a].local_in_world.inverse() * robots[b].local_in_world;
      const Rigid2d err = truth.inverse() * (ga->inverse() * *gb);
      worst_t = std::max(worst_t, err.translation().norm());
      worst_r = std::max(worst_r, std::abs(err.rotation()));
      ++pairs;
      std::printf("  %s-%s: %.4f m %.4f deg\n", robots[a].id.c_str(), robots[b].id.c_str(), err.translation().norm(),
                  std::abs(err.rotation()) * 180 / M_PI);
    }
  }
  if (c.diagnose) {
    // Every graph edge's measurement against the truth, worst per kind.
    const auto truth_node = [&](const NodeId& n) {
      const SimRobot& r = find(n.robot);
      return r.local_in_world * r.trajectory[static_cast<size_t>(n.submap * c.scans_per_submap)].pose;
    };
    std::map<std::string, std::pair<double, int>> worst;
    for (const RelativeEdge& e : engine.graph().edges()) {
      const Rigid2d truth = truth_node(e.from).inverse() * truth_node(e.to);
      const double err = (truth.inverse() * e.to_in_from).translation().norm();
      auto& w = worst[EdgeKindName(e.kind)];
      w.first = std::max(w.first, err);
      ++w.second;
    }
    for (const DetectionEdge& e : engine.graph().detections()) {
      const Rigid2d a = truth_node(e.observer) * e.observer_robot_in_node;
      const Rigid2d b = truth_node(e.observed) * e.observed_robot_in_node;
      auto& w = worst["detection"];
      w.first = std::max(w.first, (a.inverse() * b.translation() - e.position).norm());
      ++w.second;
    }
    for (const auto& [kind, w] : worst) std::printf("  worst %s edge error %.4f m (%d edges)\n", kind.c_str(), w.first, w.second);
  }
  // Merged map against the true walls.
  const auto map = engine.RenderGlobalMap(std::nullopt, 0.05);
  const SimRobot& ref = find(engine.reference_robot());
  const Rigid2d global_to_world = ref.local_in_world * engine.RobotToGlobal(ref.id)->inverse();
  int64_t occupied = 0, near_wall = 0, near_wall_15 = 0;
  for (int y = 0; map && y < map->height(); ++y) {
    for (int x = 0; x < map->width(); ++x) {
      if (map->LogOdds(CellIndex(x, y)) <= 0.4f) continue;
      ++occupied;
      const double d = DistanceToWalls(building, global_to_world * map->CellCenter(CellIndex(x, y)));
      near_wall += d <= 0.05;
      near_wall_15 += d <= 0.075;
    }
  }
  const MergeQuality q = engine.Quality();
  int corrupted_total = 0;
  for (bool b : corrupted) corrupted_total += b;
  std::printf("\nrobots %d, submaps %zu, placed %zu, detections %d (%d corrupted: %d rejected, %d used)\n", c.robots,
              nodes, engine.PlacedRobots().size(), detections_total, corrupted_total, corrupted_rejected, corrupted_used);
  std::printf("accepted alignments %d, false merges %d (worst accepted alignment %.3f m, %.3f deg)\n", accepted_alignments,
              false_merges, worst_accept_t, worst_accept_r * 180 / M_PI);
  std::printf("final relative transform error over %d pairs: max %.4f m, %.4f deg\n", pairs, worst_t, worst_r * 180 / M_PI);
  std::printf("inter-robot residual rms %.4f m over %d edges; map disagreement %.4f (%lld / %lld cells)\n",
              q.inter_robot_rms_translation, q.inter_robot_edges, q.disagreement_fraction(),
              static_cast<long long>(q.disagreeing_cells), static_cast<long long>(q.overlapping_cells));
  std::printf("occupied cells (of %lld) whose centre is within 5 cm of a true wall: %.2f %%, within 7.5 cm: %.2f %%\n",
              static_cast<long long>(occupied), occupied ? 100.0 * static_cast<double>(near_wall) / static_cast<double>(occupied) : 0.0,
              occupied ? 100.0 * static_cast<double>(near_wall_15) / static_cast<double>(occupied) : 0.0);
  std::printf("Update() per new submap: median %.1f ms, p90 %.1f ms, max %.1f ms (all %zu)\n", Percentile(update_ms, 0.5),
              Percentile(update_ms, 0.9), Percentile(update_ms, 1.0), update_ms.size());
  std::printf("  with all robots placed: median %.1f ms, p90 %.1f ms (%zu)\n", Percentile(placed_update_ms, 0.5),
              Percentile(placed_update_ms, 0.9), placed_update_ms.size());
  std::printf("  last 40 submaps (graph of %zu-%zu): median %.1f ms, p90 %.1f ms, max %.1f ms\n", nodes - late_update_ms.size() + 1,
              nodes, Percentile(late_update_ms, 0.5), Percentile(late_update_ms, 0.9), Percentile(late_update_ms, 1.0));
  return false_merges == 0 ? 0 : 2;
}

}  // namespace
}  // namespace fleetmap::bench

int main(int argc, char** argv) {
  fleetmap::bench::Config c;
  CLI::App app{"Merge engine benchmark on a synthetic building with unknown robot start frames"};
  app.add_option("--robots", c.robots, "Number of robots")->check(CLI::Range(2, 16));
  app.add_option("--submaps-per-robot", c.submaps_per_robot, "Submaps each robot builds")->check(CLI::Range(2, 1000));
  app.add_option("--scans-per-submap", c.scans_per_submap, "Scans per submap")->check(CLI::Range(1, 100));
  app.add_option("--rooms-x", c.rooms_x, "Rooms along x")->check(CLI::Range(1, 20));
  app.add_option("--rooms-y", c.rooms_y, "Rooms along y")->check(CLI::Range(1, 20));
  app.add_option("--seed", c.seed, "Random seed");
  app.add_option("--whole-map-ambiguity", c.whole_map_ambiguity,
                 "A join on matches alone waits while another alignment of the whole maps "
                 "scores this share of it (MergeEngineOptions::whole_map_ambiguity; 0: no check)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--whole-map-min-contradictions", c.whole_map_min_contradictions,
                 "An alternative alignment of the whole maps stops blocking a join when that many "
                 "of their walls cross seen-free space there, plus 4 times the join's, and a join "
                 "that puts this many there itself waits "
                 "(MergeEngineOptions::whole_map_min_contradictions; 0: never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--whole-map-rule-out-higher", c.whole_map_rule_out_higher,
                 "The walls also rule out alternatives scoring more than the join, counted with "
                 "their tiles fitted (MergeEngineOptions::whole_map_rule_out_higher)")
      ->capture_default_str();
  app.add_option("--cross-retry-growth", c.cross_retry_growth,
                 "a submap not yet joined is searched over another component's map again once "
                 "that map holds this many times as many finished submaps "
                 "(MergeEngineOptions::cross_retry_growth; 0: once)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--edge-refine-window", c.edge_refine_window,
                 "each match edge refined again against its from-node's submap alone within this "
                 "many metres (MergeEngineOptions::edge_refine_window; 0: not refined)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--search-threads", c.search_threads,
                 "threads for an update's searches that do not depend on each other; the "
                 "results are the same for any count (MergeEngineOptions::search_threads; 0: one "
                 "per core, at most an update's nearby searches)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--outlier-fraction", c.outlier_fraction, "Fraction of corrupted detections")->check(CLI::Range(0.0, 1.0));
  app.add_option("--detection-sigma", c.detection_sigma, "Detection position noise (m)");
  bool no_detections = false;
  app.add_flag("--no-detections", no_detections, "Merge from submap matching alone");
  bool no_local = false;
  app.add_flag("--no-local-constraints", no_local, "Only alignment edges between robots");
  app.add_flag("--verbose", c.verbose, "Print every alignment event with its reason");
  app.add_flag("--diagnose", c.diagnose, "Print every edge kind's worst error against the truth");
  CLI11_PARSE(app, argc, argv);
  c.local_constraints = !no_local;
  c.detections = !no_detections;
  try {
    return fleetmap::bench::Run(c);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
