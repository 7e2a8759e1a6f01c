#ifndef FLEETMAP_ROBOT_AGENT_AGENT_MAPPING_PIPELINE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_MAPPING_PIPELINE_H_

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "robot_agent/agent/detection_stage.h"
#include "robot_agent/agent/outbox.h"
#include "robot_agent/detection/laser_body.h"
#include "robot_agent/slam/seen_robot_mask.h"
#include "robot_agent/agent/sensor_source.h"
#include "robot_agent/slam/local_slam.h"
#include "shared/core/robot_detection.h"

namespace fleetmap {

struct MappingPipelineOptions {
  std::string robot_id;
  // Seconds of sensor time between trajectory revisions (0: only at the end), and between
  // snapshots of the submap still being built (0: finished submaps only).
  double trajectory_period = 5.0;
  double active_submap_period = 0.0;
  int zstd_level = 1;
  // Returns off robots the camera detected are kept out of local SLAM (seen_robot_mask.h).
  bool mask_seen_robots = true;
  SeenRobotMaskOptions mask;
  // > 0: also mask free-standing round bodies of this radius that the laser alone finds
  // (laser_body.h): robots beside or behind the camera's view, or with no camera at all.
  double laser_body_radius = 0.0;
  LaserBodyOptions laser_bodies;
};

// Counters, readable from other threads (status lines).
struct PipelineCounters {
  std::atomic<int64_t> odometry{0};
  std::atomic<int64_t> scans{0};
  std::atomic<int64_t> camera_frames{0};
  std::atomic<int64_t> refused_inputs{0};  // the backend refused them (time order, malformed)
  std::atomic<int64_t> submaps_queued{0};  // submap revisions written to the outbox
  std::atomic<int64_t> finished_submaps_queued{0};
  std::atomic<int64_t> trajectories_queued{0};
  std::atomic<int64_t> detections_queued{0};
  std::atomic<int64_t> masked_returns{0};  // laser returns off detected robots, kept out of SLAM
  std::atomic<int64_t> laser_bodies{0};    // round bodies the laser alone found (and masked)
};

// sensor event -> local SLAM -> outbox: feeds the backend in time order and writes every
// finished submap, submap revision, trajectory revision and detection to the outbox before
// anything is sent. Keys are deterministic (a replay of the same data produces the same keys),
// so that re-running after a restart duplicates nothing on the server.
class MappingPipeline {
 public:
  // `now` is the Unix clock for the outbox; `on_queued` is called after each enqueue (wakes the
  // uploader).
  MappingPipeline(const MappingPipelineOptions& options, std::unique_ptr<LocalSlam> slam,
                  Outbox* outbox, std::function<double()> now,
                  std::function<void()> on_queued = nullptr);

  // False only when the outbox failed (the agent cannot go on without it). Bad sensor data is
  // counted and skipped.
  bool Process(const SensorEvent& event, std::string* error);
  bool AddDetections(const std::vector<RobotDetection>& detections, std::string* error);
  // Camera frames then go through `stage` (paired with scans) and its detections to the outbox.
  void SetDetectionStage(std::unique_ptr<DetectionStage> stage) { detection_ = std::move(stage); }
  const DetectionStage* detection_stage() const { return detection_.get(); }
  // Called on the caller's thread with each detection as it is made (after the scan it was
  // paired with went to the backend); e.g. to tell the seen robot where it is.
  void SetDetectionListener(std::function<void(const RobotDetection&)> listener) {
    detection_listener_ = std::move(listener);
  }
  // End of input: finishes the active submap and queues it and the final trajectory.
  bool Finish(std::string* error);

  const PipelineCounters& counters() const { return counters_; }
  const LocalSlam& slam() const { return *slam_; }
  // The last refusal by the backend (for logs).
  const std::string& last_refusal() const { return last_refusal_; }

  // The trajectory revision number: grows with the backend's own revision and with every new
  // pose, and is the same for the same data.
  static int64_t TrajectoryRevision(int64_t backend_revision, size_t poses);
  // A detection's id: from its time (ms) and the observed robot, the same on a replay.
  static int64_t DetectionId(const RobotDetection& detection);

 private:
  bool QueueSubmaps(bool force_active, std::string* error);
  bool QueueTrajectory(std::string* error);
  bool Enqueue(const OutboxKey& key, const std::string& payload, bool supersede,
               std::string* error);

  const MappingPipelineOptions options_;
  std::unique_ptr<LocalSlam> slam_;
  std::unique_ptr<DetectionStage> detection_;  // optional
  std::function<void(const RobotDetection&)> detection_listener_;  // optional
  Outbox* const outbox_;
  const std::function<double()> now_;
  const std::function<void()> on_queued_;
  PipelineCounters counters_;
  SeenRobotMask mask_;
  bool laser_carries_odometry_ = false;  // then ODOM lines are left out
  std::optional<Rigid2d> first_laser_odometry_;
  double last_trajectory_time_ = -1e300;
  double last_active_submap_time_ = -1e300;
  int64_t last_trajectory_revision_ = -1;
  double sensor_time_ = 0.0;
  std::string last_refusal_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_MAPPING_PIPELINE_H_
