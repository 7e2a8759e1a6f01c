#include "robot_agent/localization/tool/sim_replay.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <random>

#include "robot_agent/sim/simulation.h"
#include "shared/core/likelihood_field.h"
#include "shared/io/map_file.h"

namespace fleetmap {
namespace {

// The simulated detection: the true relative position seen with range/bearing noise, and the
// covariance of that noise linearized at the measurement.
RobotDetection SimulateDetection(const sim::VisibilityRecord& record, bool mutual,
                                 const SimLocalizationOptions& options,
                                 const std::vector<std::string>& names, std::mt19937& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  const double range = record.range + options.range_std * normal(rng);
  const double bearing = record.bearing + options.bearing_std * normal(rng);
  RobotDetection detection;
  detection.observer_id = names[static_cast<size_t>(record.observer)];
  detection.observed_id = names[static_cast<size_t>(record.observed)];
  detection.timestamp = record.timestamp;
  const double c = std::cos(bearing), s = std::sin(bearing);
  detection.position_in_observer = Eigen::Vector2d(range * c, range * s);
  Eigen::Matrix2d jacobian;
  jacobian << c, -range * s, s, range * c;
  const Eigen::Vector2d variances(options.range_std * options.range_std,
                                  options.bearing_std * options.bearing_std);
  detection.covariance = jacobian * variances.asDiagonal() * jacobian.transpose();
  if (mutual) {
    detection.relative_heading =
        NormalizeAngle(record.relative.rotation() + options.relative_heading_std * normal(rng));
    detection.relative_heading_variance =
        options.relative_heading_std * options.relative_heading_std;
  }
  return detection;
}

bool SeenWithinRange(const sim::VisibilityRecord& record, double max_range) {
  return record.visible && record.range <= max_range;
}

}  // namespace

bool LoadWorldMap(const std::string& world_path, OccupancyGrid* grid, std::string* error) {
  const std::string suffix = ".world.yaml";
  std::string map_path = world_path;
  if (map_path.size() > suffix.size() &&
      map_path.compare(map_path.size() - suffix.size(), suffix.size(), suffix) == 0) {
    map_path = map_path.substr(0, map_path.size() - suffix.size()) + ".yaml";
  }
  return ReadMap(map_path, grid, error);
}

double FirstLocalizedTime(const ErrorSeries& position, const ErrorSeries& heading,
                          double position_tolerance, double heading_tolerance, double hold) {
  const size_t n = std::min(position.points.size(), heading.points.size());
  double start = -1.0;
  for (size_t i = 0; i < n; ++i) {
    const double t = position.points[i].first;
    const bool ok = position.points[i].second <= position_tolerance &&
                    heading.points[i].second <= heading_tolerance;
    if (!ok) {
      start = -1.0;
      continue;
    }
    if (start < 0.0) start = t;
    if (t - start >= hold) return start;
  }
  return -1.0;
}

bool RunSimLocalization(const sim::Scenario& scenario, const sim::World& world,
                        const OccupancyGrid& map, const SimLocalizationOptions& options,
                        SimRunResult* result, std::string* error) {
  sim::Scenario quiet = scenario;
  quiet.camera.enabled = false;  // visibility records are computed without rendering
  std::unique_ptr<sim::Simulation> simulation = sim::Simulation::Create(quiet, world, error);
  if (!simulation) return false;
  const size_t robot_count = simulation->robots().size();
  if (options.lost_robot < 0 || static_cast<size_t>(options.lost_robot) >= robot_count) {
    *error = "lost robot index " + std::to_string(options.lost_robot) + " out of range (" +
             std::to_string(robot_count) + " robots)";
    return false;
  }
  if (options.max_time > 0.0) simulation->set_end_time(options.max_time);

  const LikelihoodField field(map, LikelihoodFieldOptions());
  LikelihoodFieldModel model(field, options.laser);
  const FreeSpace free_space = FreeSpace::FromGrid(map);
  std::vector<std::unique_ptr<Mcl>> filters;
  std::vector<std::string> names;
  *result = SimRunResult();
  const std::vector<Rigid2d> starts = simulation->TruePoses();
  for (size_t r = 0; r < robot_count; ++r) {
    MclOptions mcl_options = options.mcl;
    mcl_options.seed = options.seed * 7919u + static_cast<uint32_t>(r) * 104729u + 1u;
    mcl_options.kld.max_particles = options.particles;
    mcl_options.kld.min_particles = std::min(mcl_options.kld.min_particles, options.particles);
    filters.push_back(std::make_unique<Mcl>(free_space, mcl_options));
    if (static_cast<int>(r) == options.lost_robot) {
      filters.back()->InitializeUniform();
    } else {
      const double p = options.start_position_std * options.start_position_std;
      const double h = options.start_heading_std * options.start_heading_std;
      filters.back()->InitializeGaussian(starts[r], Eigen::Vector3d(p, p, h).asDiagonal());
    }
    names.push_back(simulation->robots()[r].name);
    SimRobotResult robot;
    robot.name = names.back();
    robot.position_error.name = robot.heading_error.name = robot.name;
    result->robots.push_back(robot);
  }

  std::mt19937 detection_rng(options.seed * 31u + 7u);
  DetectionGate gate(options.detection_interval, options.lost_detection_interval);
  std::vector<std::optional<Rigid2d>> last_odometry(robot_count);
  while (!simulation->Done()) {
    const sim::StepResult step = simulation->Step();
    for (const sim::SensorPacket& packet : step.packets) {
      if (!packet.laser) continue;
      const size_t r = static_cast<size_t>(packet.robot_index);
      if (r >= robot_count) continue;
      const Rigid2d& odometry = packet.laser->robot_pose;
      if (last_odometry[r]) filters[r]->Predict(last_odometry[r]->inverse() * odometry);
      last_odometry[r] = odometry;
      filters[r]->UpdateLaser(packet.laser->scan, model);
      const PoseEstimate estimate = filters[r]->Estimate();
      const Rigid2d& truth = packet.ground_truth;
      SimRobotResult& robot = result->robots[r];
      robot.position_error.points.emplace_back(
          packet.timestamp, (estimate.robot_in_map.translation() - truth.translation()).norm());
      robot.heading_error.points.emplace_back(
          packet.timestamp,
          std::abs(NormalizeAngle(estimate.robot_in_map.rotation() - truth.rotation())));
    }
    for (const sim::VisibilityRecord& record : step.visibility) {
      if (!SeenWithinRange(record, options.detection_max_range)) continue;
      ++result->detections_visible;
      if (record.observed == options.lost_robot && result->first_visible_time < 0.0) {
        result->first_visible_time = record.timestamp;
      }
      if (!options.detections) continue;
      // The pipeline knows the relative heading when the other robot sees this one too.
      bool mutual = false;
      for (const sim::VisibilityRecord& other : step.visibility) {
        mutual |= other.observer == record.observed && other.observed == record.observer &&
                  SeenWithinRange(other, options.detection_max_range);
      }
      const RobotDetection detection =
          SimulateDetection(record, mutual, options, names, detection_rng);
      Mcl& observer = *filters[static_cast<size_t>(record.observer)];
      const auto density =
          SummarizeDetection(observer.particles(), detection, options.summary, observer.rng());
      Mcl& observed = *filters[static_cast<size_t>(record.observed)];
      if (!density || !gate.Allow(detection.observer_id, detection.observed_id, record.timestamp,
                                  observed.globally_localizing())) {
        continue;
      }
      if (ApplyPoseDensity(*density, options.density, &observed)) {
        ++result->detections_used;
        if (record.observed == options.lost_robot && result->first_detection_time < 0.0) {
          result->first_detection_time = record.timestamp;
        }
      }
    }
  }
  result->end_time = simulation->time();
  for (SimRobotResult& robot : result->robots) {
    robot.time_localized =
        FirstLocalizedTime(robot.position_error, robot.heading_error, options.position_tolerance,
                           options.heading_tolerance, options.hold_time);
    robot.localized_at_end =
        !robot.position_error.points.empty() &&
        robot.position_error.points.back().second <= options.position_tolerance &&
        robot.heading_error.points.back().second <= options.heading_tolerance;
  }
  return true;
}

}  // namespace fleetmap
