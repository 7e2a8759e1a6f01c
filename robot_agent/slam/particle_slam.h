#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SLAM_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SLAM_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "robot_agent/slam/local_slam.h"
#include "robot_agent/slam/odometry_buffer.h"
#include "robot_agent/slam/particle_filter.h"
#include "robot_agent/slam/particle_loop_closure.h"
#include "robot_agent/slam/particle_submaps.h"
#include "robot_agent/slam/scan_matching_slam.h"
#include "shared/core/thread_pool.h"

namespace fleetmap {

struct ParticleSlamOptions {
  std::string name = "rbpf";
  std::string robot_id = "robot";
  ParticleFilterOptions filter;
  // Returns farther than this are left out of matching; beams are traced at most this far.
  float max_range = 20.0f;
  // The laser-horizon trap: the map's walls end where earlier scans' horizons (min(range_max,
  // max_range)) cut them, so a new scan's returns past those ends would pull every match back
  // towards the previous pose. Returns are matched by the improved proposal only when they lie
  // within horizon - match_range_margin of the sensor at one of the latest horizon_keyframes
  // keyframes, at the tracked pose; all returns are mapped and weighted. The margin covers the
  // proposal's reach (its 20 cm search). The tracker keeps its own margin (tracker options).
  float match_range_margin = 0.3f;
  int horizon_keyframes = 10;
  // Matching and weighting use one point per voxel of this size (metres).
  float match_voxel = 0.1f;
  // A filter update (keyframe) runs when the robot moved this far (metres / radians).
  double update_translation = 1.0;
  double update_rotation = 0.5;
  // Motion input to the filter: raw odometry (false: the paper's pseudo-code) or the per-scan
  // scan-matched motion (true: the paper's remedy for FastSLAM's particle depletion). The
  // filter's motion model takes the noise of its input (filter.motion_noise is replaced by one
  // of these). Scan-matched by default for both filters: with its own noise it is better on
  // every figure (FastSLAM intel 0.059 -> 0.017 m, aces 0.063 -> 0.037 m, rectangle 3 laps
  // within 0.5 % on 0 -> 6 of 8 seeds; docs/BENCHMARKS.md, issue 5, session 12).
  bool scan_matched_motion = true;
  MotionNoise odometry_noise = MotionNoise::WheelOdometry();
  MotionNoise scan_matched_noise = MotionNoise::ScanMatched();
  // Every scan is tracked by the scan-matching backend's frontend, in its own frame (every scan
  // against its rolling local map of recent scans: scan-matched odometry). A scan between two
  // filter updates is placed at the best particle's latest keyframe moved by the tracker's
  // motion since that keyframe, so every scan gets a pose from scan matching, not odometry.
  // Before, the tracker matched each scan against the best particle's latest 10 keyframes, a
  // metre apart: its chain alone read aces 0.040 m and ended the building lap 11 m off, where
  // the frontend reads 0.037 m and 0.2 m (docs/BENCHMARKS.md, issue 5, session 11).
  ScanMatchingSlamOptions tracker = DefaultTracker();
  // The loop-closure layer's node scans keep one return per voxel of this size (metres).
  float node_voxel = 0.05f;
  // Worker threads for the per-particle work (results do not depend on it).
  int threads = 2;
  int keyframes_per_submap = 10;
  OccupancyGridOptions submap_grid;
  // Global loop closure over the best particle's settled keyframes (particle_loop_closure.h):
  // the filter alone does not close large loops (its particles have long lost the hypothesis
  // that would). When enabled, the reported trajectory and submaps are the corrected ones.
  ParticleLoopClosureOptions loop_closure;

  // Grid FastSLAM (motion-model proposal, resampling at every update) and the RBPF with
  // improved proposal and selective resampling (GMapping-like defaults, but driven by the
  // scan-matched motion with its own noise, the RBPF's lattice centred on its prediction).
  static ParticleSlamOptions FastSlam();
  static ParticleSlamOptions Rbpf();
  // The scan-matching backend's options without submaps or loop closure.
  static ScanMatchingSlamOptions DefaultTracker();
};

// Local SLAM by a Rao-Blackwellized particle filter: grid FastSLAM or the improved-proposal
// RBPF, by options. The reported trajectory and submaps are the best particle's; every scan's
// pose is stored relative to its keyframe, so a resampling that changes the best particle's
// history revises the whole trajectory (trajectory_revision() grows). With loop closure on,
// every reported pose and submap is moved by the pose graph's correction, and a graph
// optimisation revises them too.
class ParticleSlam : public LocalSlam {
 public:
  explicit ParticleSlam(const ParticleSlamOptions& options);

  bool AddOdometry(const StampedPose& odometry, std::string* error) override;
  bool AddScan(const LaserScan& scan, std::string* error) override;
  Rigid2d CurrentPose() const override;
  const Trajectory& trajectory() const override { return trajectory_; }
  int64_t trajectory_revision() const override { return revision_; }
  using LocalSlam::TakeSubmapUpdates;
  std::vector<Submap> TakeSubmapUpdates(size_t max_count) override;
  void Finish() override;
  std::string Statistics() const override;

  const ParticleFilter& filter() const { return filter_; }

 private:
  // One scan in the forms the backend uses.
  struct PreparedScan {
    ParticleScan filter;  // match points inside the horizon; rays of every return
    LaserScan limited;    // returns beyond max_range dropped: what the submaps get
    std::vector<Eigen::Vector2f> node_points;  // inside the horizon: the layer's node scan
  };
  PreparedScan Prepare(const LaserScan& scan, const Rigid2d& pose) const;
  // `returns` (robot frame, beam order) that, at `pose`, lie inside a recent keyframe's
  // horizon less match_range_margin; all of them before the first keyframe.
  std::vector<Eigen::Vector2f> InsideRecentHorizons(const std::vector<Eigen::Vector2f>& returns,
                                                    const Rigid2d& pose) const;
  void AddKeyframe(const LaserScan& limited, const Rigid2d& tracker_pose);
  void RefreshBestHistory();
  void SettleAndCorrect(bool history_changed);
  // The reported pose of scan `i` from its anchor (through the loop-closure layer when on).
  Rigid2d ReportedPose(size_t scan) const;
  void ReportAllPoses();

  struct ScanAnchor {
    size_t keyframe = 0;
    Rigid2d offset;  // the scan's pose in the keyframe's frame
  };

  // options.filter with the motion noise of the chosen motion input (and the lattice on the
  // match when that input is odometry).
  static ParticleFilterOptions FilterOptions(const ParticleSlamOptions& options);

  const ParticleSlamOptions options_;
  std::unique_ptr<ThreadPool> pool_;
  ParticleFilter filter_;
  OdometryBuffer odometry_;
  ParticleSubmaps submaps_;
  ScanMatchingSlam tracker_;
  Rigid2d tracker_at_keyframe_;  // the tracker's pose at the latest keyframe (its own frame)
  std::unique_ptr<ParticleLoopClosure> loop_closure_;  // null when off
  std::set<int64_t> moved_submaps_;  // moved by the pose graph, not handed out again yet
  Trajectory trajectory_;
  std::vector<ScanAnchor> anchors_;
  std::vector<Rigid2d> keyframe_poses_;  // the best particle's
  struct KeyframeView {
    Eigen::Vector2d sensor_in_robot;
    float horizon = 0.0f;  // min(range_max, max_range)
  };
  std::vector<KeyframeView> keyframe_views_;  // one per keyframe
  Rigid2d current_pose_;
  Rigid2d odometry_since_update_;
  std::optional<Rigid2d> last_odometry_;
  double last_time_ = -1e300;
  int64_t revision_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SLAM_H_
