#include "robot_agent/sim/simulation.h"

#include <algorithm>
#include <cmath>

#include "robot_agent/sim/appearance.h"
#include "robot_agent/sim/world_io.h"

namespace fleetmap::sim {
namespace {

constexpr Rgb kBodyColor{55, 55, 60};

long PeriodTicks(double rate_hz, double time_step) {
  return std::max(1L, std::lround(1.0 / (rate_hz * time_step)));
}

}  // namespace

struct Simulation::RobotState {
  Rigid2d pose;
  PathFollower follower;
  OdometryModel odometry;
  Rng laser_rng;
  Rng camera_rng;
  double exposure = 1.0;
  double start_delay = 0.0;
};

Simulation::Simulation(const Scenario& scenario, World world)
    : scenario_(scenario),
      world_(std::move(world)),
      planner_(world_, PlannerOptionsFor(scenario)),
      laser_(scenario.laser),
      camera_(scenario.camera, Rng::ForStream(scenario.seed, 999).Next()) {}

Simulation::~Simulation() = default;

std::unique_ptr<Simulation> Simulation::Create(const Scenario& scenario, World world,
                                               std::string* error) {
  std::unique_ptr<Simulation> sim(new Simulation(scenario, std::move(world)));
  std::vector<PlannedRoute> routes;
  if (!PlanRoutes(scenario, sim->world_, sim->planner_, &routes, error)) return nullptr;
  double longest = 0.0;
  for (size_t i = 0; i < routes.size(); ++i) {
    const RobotSpec& spec = scenario.robots[i];
    sim->robots_info_.push_back(SimRobotInfo{spec.name, MarkerColor(static_cast<int>(i)),
                                             routes[i]});
    const uint64_t stream = 10 * i;
    sim->robots_.push_back(std::unique_ptr<RobotState>(new RobotState{
        routes[i].start,
        PathFollower(routes[i].path, spec.speed, scenario.body.radius, FollowerOptions()),
        OdometryModel(scenario.odometry, Rng::ForStream(scenario.seed, stream + 1).Next()),
        Rng::ForStream(scenario.seed, stream + 2), Rng::ForStream(scenario.seed, stream + 3),
        1.0, spec.start_delay}));
    longest = std::max(longest, spec.start_delay + 1.5 * PathLength(routes[i].path) / spec.speed);
  }
  const double dt = scenario.time_step;
  sim->odometry_period_ = PeriodTicks(scenario.odometry.rate_hz, dt);
  sim->laser_period_ = PeriodTicks(scenario.laser.rate_hz, dt);
  sim->camera_period_ = PeriodTicks(scenario.camera.rate_hz, dt);
  // Without a duration the run ends when every route is done; the estimate is a safety net
  // against a robot that cannot finish (e.g. blocked by another forever).
  sim->end_time_ = scenario.start_time +
                   (scenario.duration > 0 ? scenario.duration : longest + 60.0);
  return sim;
}

std::unique_ptr<Simulation> Simulation::FromFile(const std::string& scenario_path,
                                                 std::string* error, bool camera_enabled) {
  Scenario scenario;
  if (!LoadScenario(scenario_path, &scenario, error)) return nullptr;
  if (!camera_enabled) scenario.camera.enabled = false;
  World world;
  if (!LoadWorld(scenario.world_path, &world, error)) return nullptr;
  std::unique_ptr<Simulation> sim = Create(scenario, std::move(world), error);
  if (!sim) *error = scenario_path + ": " + *error;
  return sim;
}

double Simulation::time() const { return scenario_.start_time + tick_ * scenario_.time_step; }

bool Simulation::Done() const {
  const double now = time();
  if (now >= end_time_ - 1e-9) return true;
  return scenario_.duration <= 0 && all_done_time_ >= 0 && now >= all_done_time_ + 1.0;
}

std::vector<Rigid2d> Simulation::TruePoses() const {
  std::vector<Rigid2d> poses;
  for (const auto& robot : robots_) poses.push_back(robot->pose);
  return poses;
}

std::vector<Cylinder> Simulation::ObstaclesSeenBy(int robot, bool with_markers) const {
  std::vector<Cylinder> cylinders;
  const RobotBody& body = scenario_.body;
  for (int i = 0; i < static_cast<int>(robots_.size()); ++i) {
    if (i == robot) continue;
    const Eigen::Vector2d center = robots_[static_cast<size_t>(i)]->pose.translation();
    cylinders.push_back(Cylinder{center, body.radius, 0.0, body.body_height, kBodyColor});
    if (with_markers) {
      cylinders.push_back(Cylinder{center, body.marker_radius, body.marker_z_min,
                                   body.marker_z_max, robots_info_[static_cast<size_t>(i)].marker});
    }
  }
  return cylinders;
}

SensorPacket Simulation::Sense(int index, double timestamp, bool odometry, bool laser,
                               bool camera) {
  RobotState& robot = *robots_[static_cast<size_t>(index)];
  SensorPacket packet;
  packet.robot_index = index;
  packet.robot_name = robots_info_[static_cast<size_t>(index)].name;
  packet.timestamp = timestamp;
  packet.ground_truth = robot.pose;
  if (odometry) {
    OdometryRecord record;
    record.timestamp = timestamp;
    record.robot_pose = robot.odometry.pose();
    record.translational_velocity = robot.odometry.linear_velocity();
    record.rotational_velocity = robot.odometry.angular_velocity();
    packet.odometry = record;
  }
  if (laser) {
    LaserRecord record;
    record.scan = laser_.Scan(world_, robot.pose, ObstaclesSeenBy(index, false), timestamp,
                              &robot.laser_rng);
    record.robot_pose = robot.odometry.pose();
    record.laser_pose = record.robot_pose * scenario_.laser.mount;
    record.logger_timestamp = timestamp;
    packet.laser = std::move(record);
  }
  if (camera) {
    // Exposure drifts slowly around 1 (auto-exposure hunting, clouds through windows).
    const double variation = scenario_.camera.lighting_variation;
    robot.exposure += 0.1 * (1.0 - robot.exposure) + robot.camera_rng.Gaussian(0.15 * variation);
    robot.exposure = std::clamp(robot.exposure, 1.0 - variation, 1.0 + variation);
    CameraFrame frame;
    frame.timestamp = timestamp;
    frame.intrinsics = camera_.intrinsics();
    frame.mount = camera_.mount();
    frame.mount_z = scenario_.camera.mount_z;
    camera_.Render(world_, robot.pose, ObstaclesSeenBy(index, true), robot.exposure,
                   &robot.camera_rng, &frame.image);
    packet.camera = std::move(frame);
  }
  return packet;
}

void Simulation::Advance() {
  const double dt = scenario_.time_step;
  const double now = time();
  std::vector<Eigen::Vector2d> positions;
  for (const auto& robot : robots_) positions.push_back(robot->pose.translation());
  std::vector<VelocityCommand> commands(robots_.size());
  bool all_done = true;
  for (size_t i = 0; i < robots_.size(); ++i) {
    RobotState& robot = *robots_[i];
    all_done = all_done && robot.follower.done();
    if (now - scenario_.start_time < robot.start_delay) continue;
    std::vector<Eigen::Vector2d> others;
    std::vector<bool> yield_to;
    for (size_t j = 0; j < robots_.size(); ++j) {
      if (j == i) continue;
      others.push_back(positions[j]);
      // The later robot in the list waits for a moving one; a parked robot (route done) would
      // block forever, so it is only passed on the right.
      yield_to.push_back(j < i && !robots_[j]->follower.done());
    }
    commands[i] = robot.follower.Compute(robot.pose, others, yield_to, planner_);
  }
  if (all_done && all_done_time_ < 0) all_done_time_ = now;
  for (size_t i = 0; i < robots_.size(); ++i) {
    RobotState& robot = *robots_[i];
    double distance = commands[i].linear * dt;
    const double rotation = commands[i].angular * dt;
    const Rigid2d next = ApplyArc(robot.pose, distance, rotation);
    // Never drive into a wall, whatever the controller says.
    if (distance != 0.0 && !IsDiskFree(world_, next.translation(), 0.9 * scenario_.body.radius)) {
      distance = 0.0;
    }
    robot.pose = ApplyArc(robot.pose, distance, rotation);
    robot.odometry.Update(distance, rotation, dt);
  }
}

StepResult Simulation::Step() {
  StepResult result;
  result.timestamp = time();
  const bool odometry = tick_ % odometry_period_ == 0;
  const bool laser = tick_ % laser_period_ == 0;
  const bool camera_tick = tick_ % camera_period_ == 0;
  const bool camera = camera_tick && scenario_.camera.enabled;
  if (odometry || laser || camera) {
    for (int i = 0; i < static_cast<int>(robots_.size()); ++i) {
      result.packets.push_back(Sense(i, result.timestamp, odometry, laser, camera));
    }
  }
  if (camera_tick) {
    result.visibility = ComputeVisibility(result.timestamp, world_, TruePoses(), camera_,
                                          scenario_.body.radius, scenario_.body.marker_radius);
  }
  Advance();
  ++tick_;
  return result;
}

}  // namespace fleetmap::sim
