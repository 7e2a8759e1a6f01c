// SimRun: the simulator drives every robot's local SLAM, and the engine is fed as the run goes.

#include "map_server/bench/sim_run.h"

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "robot_agent/detection/laser_body.h"
#include "robot_agent/slam/backend_factory.h"

namespace fleetmap {

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

}  // namespace fleetmap
