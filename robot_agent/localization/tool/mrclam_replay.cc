#include "robot_agent/localization/tool/mrclam_replay.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace fleetmap {
namespace {

// The arena: every landmark plus a margin (the robots drive among the landmarks).
FreeSpace Arena(const MrclamDataset& dataset) {
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& [barcode, position] : dataset.landmarks) {
    lo = lo.cwiseMin(position);
    hi = hi.cwiseMax(position);
  }
  if (dataset.landmarks.empty()) lo = hi = Eigen::Vector2d::Zero();
  return FreeSpace::FromBox(lo - Eigen::Vector2d(1.0, 1.0), hi + Eigen::Vector2d(1.0, 1.0));
}

// Range/bearing to another robot as a detection with the linearized Gaussian of the sensor.
RobotDetection ToDetection(const MrclamMeasurement& m, const std::string& observer,
                           const std::string& observed, const LandmarkModelOptions& noise) {
  RobotDetection detection;
  detection.observer_id = observer;
  detection.observed_id = observed;
  detection.timestamp = m.time;
  const double c = std::cos(m.bearing), s = std::sin(m.bearing);
  detection.position_in_observer = Eigen::Vector2d(m.range * c, m.range * s);
  Eigen::Matrix2d jacobian;
  jacobian << c, -m.range * s, s, m.range * c;
  const Eigen::Vector2d variances(noise.sigma_range * noise.sigma_range,
                                  noise.sigma_bearing * noise.sigma_bearing);
  detection.covariance = jacobian * variances.asDiagonal() * jacobian.transpose();
  return detection;
}

}  // namespace

ReplayResult ReplayMrclam(const MrclamDataset& dataset, const LocalizationReplayOptions& options,
                          const std::function<void(double)>& progress) {
  const size_t robot_count = dataset.robots.size();
  std::vector<std::unique_ptr<Mcl>> filters;
  ReplayResult result;
  size_t steps = SIZE_MAX;
  for (size_t r = 0; r < robot_count; ++r) {
    MclOptions mcl_options = options.mcl;
    mcl_options.seed = options.seed + static_cast<uint32_t>(r) * 7919u;
    mcl_options.kld.max_particles = options.particles;
    mcl_options.kld.min_particles = std::min(mcl_options.kld.min_particles, options.particles);
    filters.push_back(std::make_unique<Mcl>(Arena(dataset), mcl_options));
    const MrclamRobot& robot = dataset.robots[r];
    if (options.known_start) {
      filters.back()->InitializeGaussian(robot.ground_truth.front().robot_in_map,
                                         Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal());
    } else {
      filters.back()->InitializeUniform();
    }
    steps = std::min({steps, robot.odometry.size(), robot.ground_truth.size()});
    RobotReplayResult robot_result;
    robot_result.name = "robot" + std::to_string(r + 1);
    robot_result.position_error.name = robot_result.name;
    result.robots.push_back(robot_result);
  }
  if (robot_count == 0 || steps == SIZE_MAX) return result;

  DetectionGate gate(options.detection_interval, options.lost_detection_interval);
  std::vector<Rigid2d> pending(robot_count);
  std::vector<size_t> next_measurement(robot_count, 0);
  std::vector<double> heading_error_sum(robot_count, 0.0);
  double last_predict = 0.0, next_sample = 0.0, next_progress = 0.0;
  std::vector<LandmarkObservation> observations;
  for (size_t k = 0; k + 1 < steps; ++k) {
    const double t = dataset.robots[0].odometry[k].time;
    if (options.max_time > 0.0 && t > options.max_time) break;
    bool any_measurement = false;
    for (size_t r = 0; r < robot_count; ++r) {
      const MrclamRobot& robot = dataset.robots[r];
      const size_t i = next_measurement[r];
      any_measurement |= i < robot.measurements.size() && robot.measurements[i].time <= t + 1e-6;
    }
    if (any_measurement || t - last_predict >= options.predict_interval) {
      for (size_t r = 0; r < robot_count; ++r) {
        filters[r]->Predict(pending[r]);
        pending[r] = Rigid2d();
      }
      last_predict = t;
    }
    // Landmarks first for every robot, then the detections between them.
    std::vector<std::pair<size_t, MrclamMeasurement>> robot_sightings;
    for (size_t r = 0; r < robot_count; ++r) {
      const MrclamRobot& robot = dataset.robots[r];
      observations.clear();
      size_t& i = next_measurement[r];
      for (; i < robot.measurements.size() && robot.measurements[i].time <= t + 1e-6; ++i) {
        const MrclamMeasurement& m = robot.measurements[i];
        if (dataset.robot_by_barcode.count(m.barcode)) {
          robot_sightings.emplace_back(r, m);
        } else {
          observations.push_back({m.barcode, m.range, m.bearing});
        }
      }
      if (!observations.empty()) {
        filters[r]->UpdateLandmarks(observations, dataset.landmarks, options.landmarks);
      }
    }
    for (const auto& [observer, m] : robot_sightings) {
      const size_t observed = static_cast<size_t>(dataset.robot_by_barcode.at(m.barcode));
      if (observed >= robot_count || observed == observer) continue;
      ++result.robots[observer].detections_made;
      if (!options.collaborative) continue;
      const RobotDetection detection = ToDetection(m, result.robots[observer].name,
                                                   result.robots[observed].name,
                                                   options.landmarks);
      // Check focus before spending the pair's rate budget.
      const auto density =
          SummarizeDetection(filters[observer]->particles(), detection, options.summary,
                             filters[observer]->rng());
      if (!density || !gate.Allow(detection.observer_id, detection.observed_id, t,
                                  filters[observed]->globally_localizing())) {
        continue;
      }
      if (ApplyPoseDensity(*density, options.density, filters[observed].get())) {
        ++result.robots[observer].detections_used;
      }
    }
    // Odometry (v, w) holds from this sample to the next.
    const double dt = dataset.robots[0].odometry[k + 1].time - t;
    for (size_t r = 0; r < robot_count; ++r) {
      const MrclamOdometry& o = dataset.robots[r].odometry[k];
      pending[r] = pending[r] * Rigid2d(o.v * dt, 0.0, o.w * dt);
    }
    if (t >= next_sample) {
      next_sample += options.sample_interval;
      for (size_t r = 0; r < robot_count; ++r) {
        const PoseEstimate estimate = filters[r]->Estimate();
        const Rigid2d& truth = dataset.robots[r].ground_truth[k].robot_in_map;
        const double error = (estimate.robot_in_map.translation() - truth.translation()).norm();
        RobotReplayResult& robot = result.robots[r];
        robot.position_error.points.emplace_back(t, error);
        heading_error_sum[r] +=
            std::abs(NormalizeAngle(estimate.robot_in_map.rotation() - truth.rotation()));
        if (robot.time_to_converge < 0.0 && estimate.converged && error <= options.converged_error) {
          robot.time_to_converge = t;
        }
      }
    }
    if (progress && t >= next_progress) {
      progress(t);
      next_progress += 100.0;
    }
  }
  double total = 0.0;
  size_t samples = 0;
  for (size_t r = 0; r < robot_count; ++r) {
    RobotReplayResult& robot = result.robots[r];
    double sum = 0.0;
    for (const auto& [t, e] : robot.position_error.points) sum += e;
    const size_t n = robot.position_error.points.size();
    robot.mean_position_error = n ? sum / n : 0.0;
    robot.mean_heading_error = n ? heading_error_sum[r] / n : 0.0;
    total += sum;
    samples += n;
  }
  result.mean_position_error = samples ? total / samples : 0.0;
  return result;
}

}  // namespace fleetmap
