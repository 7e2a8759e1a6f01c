#ifndef FLEETMAP_ROBOT_AGENT_SIM_MOTION_H_
#define FLEETMAP_ROBOT_AGENT_SIM_MOTION_H_

#include <vector>

#include <Eigen/Core>

#include "robot_agent/sim/path_planner.h"
#include "robot_agent/sim/rng.h"
#include "robot_agent/sim/scenario.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

// Moves `pose` along a circular arc of length `distance` turning by `rotation` (exact unicycle
// integration; used for both the ground truth and the odometry so that they agree without noise).
Rigid2d ApplyArc(const Rigid2d& pose, double distance, double rotation);

struct FollowerOptions {
  double lookahead = 0.7;            // metres ahead on the path (pure pursuit)
  double max_angular_speed = 1.2;    // rad/s
  double turn_in_place_angle = 1.0;  // radians of heading error above which the robot stops to turn
  double goal_tolerance = 0.08;      // metres
  double keep_right_offset = 0.45;   // lateral shift when another robot comes the other way
  double encounter_distance = 3.0;   // metres at which robots start keeping right
};

struct VelocityCommand {
  double linear = 0.0;   // m/s
  double angular = 0.0;  // rad/s
};

// Follows a planned path with pure pursuit; keeps right of robots ahead so two robots can pass in
// a 2 m corridor, and waits behind one that is too close (lower-priority robot waits first).
class PathFollower {
 public:
  PathFollower(Path path, double speed, double robot_radius, const FollowerOptions& options);

  // `others` are the positions of the other robots; `yield_to[i]` says whether this robot waits
  // for others[i] when they block each other.
  VelocityCommand Compute(const Rigid2d& pose, const std::vector<Eigen::Vector2d>& others,
                          const std::vector<bool>& yield_to, const PathPlanner& planner);
  bool done() const { return done_; }
  double progress() const { return progress_; }
  double length() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }

 private:
  Eigen::Vector2d PointAt(double arc_length) const;
  void UpdateProgress(const Eigen::Vector2d& position);

  const Path path_;
  const double speed_;
  const double radius_;
  const FollowerOptions options_;
  std::vector<double> cumulative_;
  size_t segment_ = 0;
  double progress_ = 0.0;
  bool done_ = false;
};

// Differential-drive wheel odometry with seeded noise and systematic errors (see
// OdometryOptions). The odometry frame starts at the identity.
class OdometryModel {
 public:
  OdometryModel(const OdometryOptions& options, uint64_t seed);
  // Feeds one time step of true motion.
  void Update(double distance, double rotation, double dt);
  const Rigid2d& pose() const { return pose_; }
  double linear_velocity() const { return linear_velocity_; }
  double angular_velocity() const { return angular_velocity_; }

 private:
  const OdometryOptions options_;
  Rng rng_;
  Rigid2d pose_;
  double linear_velocity_ = 0.0;
  double angular_velocity_ = 0.0;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_MOTION_H_
