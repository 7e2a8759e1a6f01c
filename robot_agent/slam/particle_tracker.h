#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_TRACKER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_TRACKER_H_

#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"
#include "shared/matching/scan_matcher.h"

namespace fleetmap {

struct ParticleTrackerOptions {
  // The target holds the best particle's latest keyframes (about this many metres of travel at
  // the default update distance).
  int keyframes = 10;
  // Without joining consecutive returns (MatchGridOptions::join_scan_returns): with it the RBPF's
  // building lap improved (end 5.7 -> 2.2 m) but its 3-lap rectangle height did not (0.41 ->
  // 0.87 %) and FastSLAM with scan-matched motion lost its loop (RbpfSlamTest); keyframes are a
  // metre apart here, unlike the scan-matching backend's local map.
  MatchGridOptions grid = DefaultGrid();
  ScanMatcherOptions matcher = DefaultMatcherOptions();
  // Below this refined score a correlative search runs first (bad odometry).
  double search_below_score = 0.75;
  // Along a direction that hardly any of the scan's surface normals face (a plain corridor's
  // axis; NormalScatter eigenvalue below this) the match keeps the prediction's translation.
  double min_observed_normals = 0.03;

  static ScanMatcherOptions DefaultMatcherOptions();
  static MatchGridOptions DefaultGrid();
};

// Corrects the scans between particle filter updates: each is matched (bicubic distance field,
// sub-centimetre) against the best particle's latest keyframes at that particle's poses, so
// every scan gets a pose from the map rather than from odometry alone.
class ParticleTracker {
 public:
  explicit ParticleTracker(const ParticleTrackerOptions& options = ParticleTrackerOptions());

  // A keyframe's points (robot frame), in keyframe order.
  void AddKeyframe(std::vector<Eigen::Vector2f> points);
  // Rebuilds the target from the latest keyframes at `keyframe_poses` (all keyframes so far,
  // the best particle's).
  void Rebuild(const std::vector<Rigid2d>& keyframe_poses);
  // The scan's pose, or empty when the target is empty or the match too poor. `normal_scatter`
  // is the scan's NormalScatter (robot frame).
  std::optional<Rigid2d> Track(const std::vector<Eigen::Vector2f>& points, const Rigid2d& predicted,
                               const Eigen::Matrix2d& normal_scatter) const;

 private:
  const ParticleTrackerOptions options_;
  std::deque<std::vector<Eigen::Vector2f>> recent_;  // the latest `keyframes` keyframes
  size_t keyframe_count_ = 0;
  MatchGrid target_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_TRACKER_H_
