#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_LOCALIZER_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_LOCALIZER_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/collaborative_update.h"
#include "robot_agent/localization/likelihood_field_model.h"
#include "robot_agent/localization/mcl.h"
#include "robot_agent/localization/scan_seeding.h"
#include "robot_agent/slam/local_slam.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

struct MclLocalizerOptions {
  // Augmented MCL's random injection is off here, as in AMCL's defaults: in a building of
  // look-alike corridors the random particles that land in another corridor fit as well, and
  // the belief jumps there (the simulated building lap from a known start: mean 4.4 m, lost
  // after 490 s, against 0.108 m without). Scan-to-map seeding finds a global start instead.
  MclLocalizerOptions() { mcl.recovery.enabled = false; }

  MclOptions mcl;
  LikelihoodFieldModelOptions laser;
  // Where the robot starts, in the map frame: a Gaussian around `initial_pose`, or, without
  // one, global localization from a uniform belief over the free space.
  std::optional<Rigid2d> initial_pose;
  double initial_position_std = 0.3;  // metres
  double initial_heading_std = 0.1;   // radians
  // The laser corrects the belief only once the robot has moved this much since the previous
  // correction (as AMCL's update_min_d / update_min_a); in between, odometry carries the pose.
  // A robot standing still sees the same scan again and again, and treating each as new
  // evidence makes the filter converge, often on a wrong place, within a second of a global
  // start. 0 and 0: every scan. The defaults only skip a robot (nearly) standing still: on
  // intel, 0.02 tracked as well as every scan and larger values worse (0.2 m / 0.5 rad, AMCL's:
  // relations 0.047 m against 0.035 m); docs/BENCHMARKS.md, issue 10, session 35.
  double update_min_translation = 0.02;  // metres
  double update_min_rotation = 0.02;     // radians
  // ... or, while tracking (not globally localizing), this long (seconds of sensor time) since
  // the previous correction: a robot that starts from a known pose and stands still still
  // sharpens its belief, more slowly. Not after a global start: there the same scan again
  // locks in whichever look-alike place leads (on intel, with 1 s, the truth was found after
  // 59-821 s against 30-637 s without). 0: never on time alone.
  double update_max_interval = 1.0;
  // After a global start: scan-to-map search that moves some particles to the best match.
  ScanSeedingOptions seeding;
  DensityUpdateOptions density;
  DetectionSummaryOptions summary;
  // Densities from one other robot are applied at most this often (DetectionGate): consecutive
  // ones carry almost the same information.
  double density_interval = 2.0;
  double lost_density_interval = 0.5;
  // A density says where the robot was at its timestamp: applied only while that is within
  // this many seconds of the robot's latest input (its clock and the observer's must agree,
  // e.g. NTP). Older ones (a queue that waited, a robot that replays a log) would pull the
  // belief back to where the robot was.
  double max_density_age = 1.0;
};

// Monte Carlo localization behind the agent's LocalSlam interface, so that the agent's pipeline
// (outbox, trajectory revisions, detections, masks) runs unchanged when a robot localizes in a
// known map instead of mapping. The "local map" is the known map: every pose is robot-in-map,
// and the agent registers the robot with the map's placement in the global frame (identity for
// the server's own global map). It builds no submaps.
//
// Odometry: the latest reading at each scan (the agent feeds the one a log's laser line carries
// just before its scan) moves the particles when the laser corrects them, and carries the
// reported pose in between (MclLocalizerOptions::update_min_translation). Poses already
// reported are never revised.
class MclLocalizer : public LocalSlam {
 public:
  MclLocalizer(const OccupancyGrid& map, const MclLocalizerOptions& options);

  bool AddOdometry(const StampedPose& odometry, std::string* error) override;
  bool AddScan(const LaserScan& scan, std::string* error) override;
  Rigid2d CurrentPose() const override;
  const Trajectory& trajectory() const override { return trajectory_; }
  int64_t trajectory_revision() const override { return 0; }
  using LocalSlam::TakeSubmapUpdates;
  std::vector<Submap> TakeSubmapUpdates(size_t) override { return {}; }
  void Finish() override {}
  std::string Statistics() const override;

  // The belief after the latest scan.
  const PoseEstimate& estimate() const { return estimate_; }
  // Seconds of sensor time from the first scan until the estimate first converged (< 0: not
  // yet).
  double time_to_converge() const { return time_to_converge_; }
  const Mcl& filter() const { return mcl_; }

  // Replaces the map (a newer version of it) between scans; the belief is kept as it is.
  void SetMap(const OccupancyGrid& map);

  // Collaborative update (eq. 15 of the paper), observer side: where the robot this one just
  // detected is, from this robot's belief; nullopt while this robot is not focused enough to
  // speak (DetectionSummaryOptions) or the detection is malformed.
  std::optional<PoseDensity> DensityOfSeenRobot(const RobotDetection& detection);
  // Observed side: another robot's density of this robot's pose. False (belief unchanged) when
  // it was unusable, stale (max_density_age) or came too soon after the previous one from the
  // same robot. Counted in Statistics().
  bool ApplyDensity(const PoseDensity& density);

 private:
  // Moves the particles by the odometry since they were last moved.
  void FlushMotion();
  // The odometry increment since the particles were last moved.
  Rigid2d PendingMotion() const;
  // After a global start, before a correction: some particles to where the scan fits best.
  void SeedFromScan(const LaserScan& scan);

  Mcl mcl_;
  LikelihoodFieldModel model_;
  const MclLocalizerOptions options_;
  Trajectory trajectory_;
  PoseEstimate estimate_;
  std::optional<StampedPose> odometry_;           // the latest reading
  std::optional<Rigid2d> odometry_at_particles_;  // the reading the particles were moved to
  int64_t updates_ = 0;                           // laser corrections
  std::unique_ptr<ScanSeeder> seeder_;            // after a global start, until it agrees
  double last_seed_time_ = -1e300;
  int seed_agreements_ = 0;
  int64_t seeds_ = 0;
  double last_update_time_ = 0.0;
  double last_input_time_ = -1e300;
  double first_scan_time_ = 0.0;
  double time_to_converge_ = -1.0;
  DetectionGate gate_;
  int64_t densities_sent_ = 0;
  int64_t densities_skipped_ = 0;  // by the gate
  int64_t densities_stale_ = 0;    // too old or too new (max_density_age)
  int64_t densities_applied_ = 0;
  int64_t densities_refused_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_MCL_LOCALIZER_H_
