#include "robot_agent/agent/mapping_pipeline.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "robot_agent/agent/proto_conversions.h"

namespace fleetmap {

MappingPipeline::MappingPipeline(const MappingPipelineOptions& options,
                                 std::unique_ptr<LocalSlam> slam, Outbox* outbox,
                                 std::function<double()> now, std::function<void()> on_queued)
    : options_(options),
      slam_(std::move(slam)),
      outbox_(outbox),
      now_(std::move(now)),
      on_queued_(std::move(on_queued)),
      mask_(options.mask) {}

int64_t MappingPipeline::TrajectoryRevision(int64_t backend_revision, size_t poses) {
  return (backend_revision << 32) + static_cast<int64_t>(poses & 0xffffffffu);
}

int64_t MappingPipeline::DetectionId(const RobotDetection& detection) {
  // FNV-1a: stable across builds, unlike std::hash.
  uint64_t hash = 1469598103934665603ull;
  for (unsigned char c : detection.observed_id) hash = (hash ^ c) * 1099511628211ull;
  const int64_t millis = std::llround(std::max(0.0, detection.timestamp) * 1000.0);
  return millis * 1000 + static_cast<int64_t>(hash % 1000);
}

bool MappingPipeline::Enqueue(const OutboxKey& key, const std::string& payload, bool supersede,
                              std::string* error) {
  bool inserted = false;
  if (!outbox_->Enqueue(key, payload, now_(), supersede, &inserted, error)) return false;
  if (on_queued_) on_queued_();
  return true;
}

bool MappingPipeline::Process(const SensorEvent& event, std::string* error) {
  if (sensor_time_ == 0.0) {
    last_trajectory_time_ = event.timestamp;
    last_active_submap_time_ = event.timestamp;
  }
  sensor_time_ = event.timestamp;
  std::string refusal;
  if (event.odometry) {
    ++counters_.odometry;
    // A log whose laser lines carry odometry is fed from those (one reading per scan, the
    // same clock); its ODOM lines would only interleave out of order.
    if (!laser_carries_odometry_ &&
        !slam_->AddOdometry({event.odometry->timestamp, event.odometry->robot_pose}, &refusal)) {
      ++counters_.refused_inputs;
      last_refusal_ = refusal;
    }
    if (!laser_carries_odometry_) mask_.AddOdometry(event.odometry->timestamp, event.odometry->robot_pose);
  }
  if (event.camera) ++counters_.camera_frames;
  if (event.laser) {
    const LaserRecord& laser = *event.laser;
    if (!first_laser_odometry_) first_laser_odometry_ = laser.robot_pose;
    const Rigid2d moved = first_laser_odometry_->inverse() * laser.robot_pose;
    if (moved.translation().norm() > 1e-9 || std::abs(moved.rotation()) > 1e-9) {
      laser_carries_odometry_ = true;
    }
    if (laser_carries_odometry_ &&
        !slam_->AddOdometry({laser.scan.timestamp, laser.robot_pose}, &refusal)) {
      last_refusal_ = refusal;  // e.g. the same instant as an ODOM line: harmless
    }
    if (laser_carries_odometry_) mask_.AddOdometry(laser.scan.timestamp, laser.robot_pose);
    ++counters_.scans;
    const LaserScan* scan = &laser.scan;
    LaserScan masked;
    if (options_.mask_seen_robots && options_.laser_body_radius > 0.0) {
      const std::vector<Eigen::Vector2d> bodies =
          FindLaserBodies(laser.scan, options_.laser_body_radius, options_.laser_bodies);
      counters_.laser_bodies += static_cast<int64_t>(bodies.size());
      mask_.AddLaserBodies(laser.scan.timestamp, bodies);
    }
    if (options_.mask_seen_robots && !mask_.empty()) {
      masked = laser.scan;
      const int n = mask_.Apply(&masked);
      counters_.masked_returns += n;
      if (n > 0) scan = &masked;
    }
    if (!slam_->AddScan(*scan, &refusal)) {
      ++counters_.refused_inputs;
      last_refusal_ = refusal;
    }
    if (!QueueSubmaps(/*force_active=*/false, error)) return false;
    if (options_.trajectory_period > 0.0 &&
        event.timestamp - last_trajectory_time_ >= options_.trajectory_period) {
      last_trajectory_time_ = event.timestamp;
      if (!QueueTrajectory(error)) return false;
    }
  }
  if (detection_ && (event.laser || event.camera)) {
    std::vector<RobotDetection> detections;
    detection_->Process(event, &detections);
    for (const RobotDetection& d : detections) {
      mask_.AddDetection(d);
      if (detection_listener_) detection_listener_(d);
    }
    if (!AddDetections(detections, error)) return false;
  }
  return true;
}

bool MappingPipeline::QueueSubmaps(bool force_active, std::string* error) {
  const bool active_due =
      force_active || (options_.active_submap_period > 0.0 &&
                       sensor_time_ - last_active_submap_time_ >= options_.active_submap_period);
  // A few at a time, so that a loop closure that moves every submap is not rendered all at once.
  constexpr size_t kBatch = 4;
  for (std::vector<Submap> batch = slam_->TakeSubmapUpdates(kBatch); !batch.empty();
       batch = slam_->TakeSubmapUpdates(kBatch)) {
    for (const Submap& submap : batch) {
      // Snapshots of the submap being built are skipped between periods; the next one carries a
      // higher revision, so skipping loses nothing.
      if (!submap.finished && !active_due) continue;
      if (!submap.finished) last_active_submap_time_ = sensor_time_;
      const OutboxKey key{options_.robot_id, OutboxKind::kSubmap, submap.submap_id, submap.revision};
      if (!Enqueue(key, agent::ToProto(submap, options_.zstd_level).SerializeAsString(),
                   /*supersede=*/true, error)) {
        return false;
      }
      ++counters_.submaps_queued;
      if (submap.finished) ++counters_.finished_submaps_queued;
    }
  }
  return true;
}

bool MappingPipeline::QueueTrajectory(std::string* error) {
  const Trajectory& trajectory = slam_->trajectory();
  if (trajectory.empty()) return true;
  const int64_t revision = TrajectoryRevision(slam_->trajectory_revision(), trajectory.size());
  if (revision == last_trajectory_revision_) return true;
  last_trajectory_revision_ = revision;
  const OutboxKey key{options_.robot_id, OutboxKind::kTrajectory, 0, revision};
  if (!Enqueue(
          key,
          agent::ToTrajectoryRequest(options_.robot_id, revision, trajectory).SerializeAsString(),
          /*supersede=*/true, error)) {
    return false;
  }
  ++counters_.trajectories_queued;
  return true;
}

bool MappingPipeline::AddDetections(const std::vector<RobotDetection>& detections,
                                    std::string* error) {
  for (const RobotDetection& detection : detections) {
    const int64_t id = DetectionId(detection);
    const OutboxKey key{options_.robot_id, OutboxKind::kDetection, id, 0};
    if (!Enqueue(key, agent::ToProto(detection, id).SerializeAsString(), /*supersede=*/false,
                 error)) {
      return false;
    }
    ++counters_.detections_queued;
  }
  return true;
}

bool MappingPipeline::Finish(std::string* error) {
  slam_->Finish();
  if (detection_) {
    std::vector<RobotDetection> detections;
    detection_->Finish(&detections);
    if (!AddDetections(detections, error)) return false;
  }
  return QueueSubmaps(/*force_active=*/true, error) && QueueTrajectory(error);
}

}  // namespace fleetmap
