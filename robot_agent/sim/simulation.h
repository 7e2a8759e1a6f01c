#ifndef FLEETMAP_ROBOT_AGENT_SIM_SIMULATION_H_
#define FLEETMAP_ROBOT_AGENT_SIM_SIMULATION_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "robot_agent/sim/camera_model.h"
#include "robot_agent/sim/laser_model.h"
#include "robot_agent/sim/motion.h"
#include "robot_agent/sim/path_planner.h"
#include "robot_agent/sim/routes.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/visibility.h"
#include "robot_agent/sim/world.h"
#include "shared/io/carmen_log.h"

namespace fleetmap::sim {

struct CameraFrame {
  double timestamp = 0.0;
  RgbImage image;
  CameraIntrinsics intrinsics;
  Rigid2d mount;         // camera in the robot frame (x forward, y left, yaw)
  double mount_z = 0.0;  // camera height above the floor
};

// What one robot's sensors produced at one tick. Any of the three may be absent (sensors run at
// their own rates). `ground_truth` is the true pose at `timestamp`.
struct SensorPacket {
  int robot_index = 0;
  std::string robot_name;
  double timestamp = 0.0;
  Rigid2d ground_truth;
  std::optional<OdometryRecord> odometry;
  std::optional<LaserRecord> laser;  // robot_pose / laser_pose in the odometry frame
  std::optional<CameraFrame> camera;
};

struct StepResult {
  double timestamp = 0.0;
  std::vector<SensorPacket> packets;
  std::vector<VisibilityRecord> visibility;  // at camera ticks (even with the camera disabled)
};

struct SimRobotInfo {
  std::string name;
  Rgb marker;
  PlannedRoute route;
};

// Several robots driving their routes in a world. Step() advances one time step and returns the
// sensor readings of the tick it started at; call it until Done(). Deterministic for a seed.
class Simulation {
 public:
  // Validates the scenario against the world and plans the routes; nullptr + `error` on failure.
  static std::unique_ptr<Simulation> Create(const Scenario& scenario, World world,
                                            std::string* error);
  // Loads the scenario file and its world, then Create().
  static std::unique_ptr<Simulation> FromFile(const std::string& scenario_path,
                                              std::string* error, bool camera_enabled = true);

  ~Simulation();

  StepResult Step();
  bool Done() const;
  double time() const;
  // When the run ends: the scenario's duration, or an estimate from the routes' lengths.
  double end_time() const { return end_time_; }
  // Ends the run at `time` (e.g. --duration); 0 keeps the scenario's setting.
  void set_end_time(double time) { if (time > 0) end_time_ = time; }

  const Scenario& scenario() const { return scenario_; }
  const World& world() const { return world_; }
  const std::vector<SimRobotInfo>& robots() const { return robots_info_; }
  const CameraModel& camera() const { return camera_; }
  std::vector<Rigid2d> TruePoses() const;

 private:
  struct RobotState;
  Simulation(const Scenario& scenario, World world);

  std::vector<Cylinder> ObstaclesSeenBy(int robot, bool with_markers) const;
  SensorPacket Sense(int robot, double timestamp, bool odometry, bool laser, bool camera);
  void Advance();

  const Scenario scenario_;
  const World world_;
  const PathPlanner planner_;
  const LaserModel laser_;
  const CameraModel camera_;
  std::vector<SimRobotInfo> robots_info_;
  std::vector<std::unique_ptr<RobotState>> robots_;
  long tick_ = 0;
  long odometry_period_ = 1;
  long laser_period_ = 1;
  long camera_period_ = 1;
  double end_time_ = 0.0;
  double all_done_time_ = -1.0;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_SIMULATION_H_
