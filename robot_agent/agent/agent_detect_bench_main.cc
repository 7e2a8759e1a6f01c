// fleetmap-agent-detect-bench: the agent's detection stage on every robot of a simulator
// scenario, exactly as fleetmap-agent runs it (live SimSource with camera, colours learnt at
// start), compared with the simulator's ground truth: detections per robot, position error,
// recall over the sightings the simulator marks visible (and within the laser's range).
#include <CLI/CLI.hpp>
#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

#include "robot_agent/agent/detection_factory.h"
#include "robot_agent/agent/sim_source.h"
#include "robot_agent/sim/simulation.h"

namespace {

using fleetmap::Rigid2d;

struct Truth {
  std::map<long, std::vector<Rigid2d>> poses;  // tick (ms) -> robots
  std::map<std::pair<int, int>, int> visible;  // (observer, observed) -> count
  std::map<std::pair<int, int>, std::map<long, bool>> visible_at;
};

long Tick(double t) { return std::lround(t * 1000.0); }

bool GroundTruth(const std::string& scenario, double max_range, Truth* truth, std::string* error) {
  auto simulation = fleetmap::sim::Simulation::FromFile(scenario, error, /*camera_enabled=*/false);
  if (!simulation) return false;
  while (!simulation->Done()) {
    truth->poses[Tick(simulation->time())] = simulation->TruePoses();
    for (const auto& v : simulation->Step().visibility) {
      if (!v.visible || v.range > max_range) continue;
      ++truth->visible[{v.observer, v.observed}];
      truth->visible_at[{v.observer, v.observed}][Tick(v.timestamp)] = true;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "fleetmap-agent-detect-bench: detections of the agent's detection stage on a "
      "simulator scenario vs ground truth"};
  std::string scenario = "department_3robots";
  double max_range = 8.0;
  int learn_views = 48;
  app.add_option("--scenario", scenario, "scenario file or shipped scenario name")
      ->capture_default_str();
  app.add_option("--max-range", max_range, "recall counts sightings up to this range (m)")
      ->capture_default_str();
  app.add_option("--learn-views", learn_views, "rendered frames to learn colours from")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  std::string error;
  std::string resolved = scenario;
  if (!std::filesystem::exists(resolved)) {
    resolved = fleetmap::sim::ShippedScenariosDir() + "/" + scenario + ".yaml";
  }
  fleetmap::sim::Scenario spec;
  if (!fleetmap::sim::LoadScenario(resolved, &spec, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  std::vector<std::string> names;
  for (const auto& robot : spec.robots) names.push_back(robot.name);
  Truth truth;
  std::printf("ground truth: %s ...\n", resolved.c_str());
  std::fflush(stdout);
  if (!GroundTruth(resolved, max_range, &truth, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  std::printf(
      "| observer | frames | detections | of which | error RMS (cm) | error max (cm) | "
      "recall (visible, <= %.0f m) | within 2 sigma | time (s) "
      "|\n|---|---|---|---|---|---|---|---|---|\n",
      max_range);
  for (size_t observer = 0; observer < names.size(); ++observer) {
    const auto start = std::chrono::steady_clock::now();
    fleetmap::AgentConfig config;
    config.robot_id = names[observer];
    config.source.type = fleetmap::SourceConfig::Type::kSimulator;
    config.source.scenario = resolved;
    config.source.sim_robot = names[observer];
    config.source.sim_camera = true;
    config.detection.enabled = true;
    config.detection.learn_views = learn_views;
    auto source = fleetmap::SimSource::Open(resolved, names[observer], true, &error);
    if (!source) {
      std::fprintf(stderr, "error: %s\n", error.c_str());
      return 1;
    }
    auto stage = fleetmap::CreateDetectionStage(config, *source, &error);
    if (!stage) {
      std::fprintf(stderr, "error: %s\n", error.c_str());
      return 1;
    }
    std::vector<fleetmap::RobotDetection> detections;
    fleetmap::SensorEvent event;
    while (source->Next(&event)) stage->Process(event, &detections);
    stage->Finish(&detections);
    double sum_squares = 0.0, worst = 0.0;
    int inside_2_sigma = 0, matched = 0;
    std::map<std::string, int> per_observed;
    std::map<int, int> found_visible;
    for (const auto& d : detections) {
      const auto poses = truth.poses.find(Tick(d.timestamp));
      int observed = -1;
      for (size_t i = 0; i < names.size(); ++i) {
        if (names[i] == d.observed_id) observed = static_cast<int>(i);
      }
      if (poses == truth.poses.end() || observed < 0) continue;
      ++matched;
      ++per_observed[d.observed_id];
      const Eigen::Vector2d expected = poses->second[observer].inverse() *
                                       poses->second[static_cast<size_t>(observed)].translation();
      const Eigen::Vector2d residual = d.position_in_observer - expected;
      sum_squares += residual.squaredNorm();
      worst = std::max(worst, residual.norm());
      if (residual.dot(d.covariance.inverse() * residual) <= 4.0) ++inside_2_sigma;
      const auto& at = truth.visible_at[{static_cast<int>(observer), observed}];
      if (at.count(Tick(d.timestamp))) ++found_visible[observed];
    }
    int visible = 0, found = 0;
    for (size_t i = 0; i < names.size(); ++i) {
      visible += truth.visible[{static_cast<int>(observer), static_cast<int>(i)}];
      found += found_visible[static_cast<int>(i)];
    }
    std::string of_which;
    for (const auto& [name, count] : per_observed) {
      of_which += (of_which.empty() ? "" : ", ") + name + " " + std::to_string(count);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("| %s | %lld | %d | %s | %.2f | %.2f | %.3f (%d/%d) | %.1f %% | %.1f |\n",
                names[observer].c_str(), static_cast<long long>(stage->counters().frames.load()),
                matched, of_which.empty() ? "-" : of_which.c_str(),
                matched ? 100.0 * std::sqrt(sum_squares / matched) : 0.0, 100.0 * worst,
                visible ? static_cast<double>(found) / visible : 0.0, found, visible,
                matched ? 100.0 * inside_2_sigma / matched : 0.0, seconds);
    std::fflush(stdout);
  }
  return 0;
}
