#include "tests/merge/merge_test_worlds.h"

#include <cmath>

namespace fleetmap::testing {
namespace {

LaserScan FullScan(const SegmentWorld& world, const Rigid2d& robot_in_world) {
  return SimulateScan(world, robot_in_world, 360, static_cast<float>(-M_PI),
                      static_cast<float>(M_PI / 180), 8.0f);
}

void Add(SegmentWorld* world, double ax, double ay, double bx, double by) {
  world->push_back({Eigen::Vector2d(ax, ay), Eigen::Vector2d(bx, by)});
}

}  // namespace

SegmentWorld OfficeWorld() {
  SegmentWorld world = BoxWorld(Eigen::Vector2d(0, 0), Eigen::Vector2d(20, 12));
  Add(&world, 7, 0, 7, 5);
  Add(&world, 7, 7, 7, 12);
  Add(&world, 13, 0, 13, 4);
  Add(&world, 13, 6, 13, 12);
  Add(&world, 13, 8, 17, 8);
  AddBox(Eigen::Vector2d(2, 2), Eigen::Vector2d(3, 3.5), &world);
  AddBox(Eigen::Vector2d(9, 8), Eigen::Vector2d(10.5, 8.7), &world);
  AddBox(Eigen::Vector2d(16, 2), Eigen::Vector2d(17.2, 2.6), &world);
  AddBox(Eigen::Vector2d(4.5, 9), Eigen::Vector2d(5, 10.5), &world);
  Add(&world, 15, 9.5, 18, 11);
  Add(&world, 9, 2, 11, 3.5);
  return world;
}

Rigid2d TwinOfficesHalfTurn() { return Rigid2d(40.0, 12.0, M_PI); }

SegmentWorld TwinOffices(bool crates) {
  SegmentWorld office;
  for (const Segment& s : OfficeWorld()) {
    const bool shared_wall = s.a.x() == 20.0 && s.b.x() == 20.0;
    if (!shared_wall) office.push_back(s);
  }
  office.push_back({Eigen::Vector2d(20, 0), Eigen::Vector2d(20, 5)});
  SegmentWorld world = office;
  const Rigid2d turn = TwinOfficesHalfTurn();
  for (const Segment& s : office) world.push_back({turn * s.a, turn * s.b});
  if (crates) {
    AddBox(Eigen::Vector2d(11, 9.5), Eigen::Vector2d(12.3, 11), &world);
    AddBox(Eigen::Vector2d(15, 6), Eigen::Vector2d(16.5, 7.2), &world);
  }
  return world;
}

SegmentWorld CorridorWorld() {
  SegmentWorld world;
  Add(&world, 0, 0, 30, 0);
  Add(&world, 0, 2, 30, 2);
  return world;
}

OccupancyGrid GridFromScans(const SegmentWorld& world, const std::vector<Rigid2d>& robot_in_world,
                            const Rigid2d& frame_in_world, double resolution) {
  OccupancyGridOptions options;
  options.resolution = resolution;
  OccupancyGrid grid(options);
  const Rigid2d world_in_frame = frame_in_world.inverse();
  for (const Rigid2d& pose : robot_in_world) {
    grid.InsertScan(FullScan(world, pose), world_in_frame * pose);
  }
  return grid;
}

Trajectory MakeTrajectory(const std::vector<Rigid2d>& path, const Rigid2d& local_in_world,
                          double dt) {
  Trajectory trajectory;
  const Rigid2d world_in_local = local_in_world.inverse();
  for (size_t i = 0; i < path.size(); ++i) {
    trajectory.push_back({static_cast<double>(i) * dt, world_in_local * path[i]});
  }
  return trajectory;
}

std::vector<Submap> MakeSubmaps(const std::string& robot, const SegmentWorld& world,
                                const std::vector<Rigid2d>& path, const Rigid2d& local_in_world,
                                int scans_per_submap, double dt) {
  const Trajectory trajectory = MakeTrajectory(path, local_in_world, dt);
  std::vector<Submap> submaps;
  for (size_t start = 0; start < path.size(); start += static_cast<size_t>(scans_per_submap)) {
    Submap submap;
    submap.robot_id = robot;
    submap.submap_id = static_cast<int64_t>(submaps.size());
    submap.revision = 1;
    submap.submap_in_local = trajectory[start].pose;
    submap.finished = true;
    const Rigid2d local_in_submap = submap.submap_in_local.inverse();
    for (size_t i = start; i < std::min(path.size(), start + scans_per_submap); ++i) {
      submap.scan_poses.push_back(trajectory[i]);
      submap.grid.InsertScan(FullScan(world, path[i]), local_in_submap * trajectory[i].pose);
    }
    submaps.push_back(std::move(submap));
  }
  return submaps;
}

std::vector<Rigid2d> PathThrough(const std::vector<Eigen::Vector2d>& waypoints, double step) {
  std::vector<Rigid2d> path;
  for (size_t i = 0; i + 1 < waypoints.size(); ++i) {
    const Eigen::Vector2d d = waypoints[i + 1] - waypoints[i];
    const double heading = std::atan2(d.y(), d.x());
    const int n = std::max(1, static_cast<int>(std::ceil(d.norm() / step)));
    for (int k = 0; k < n; ++k) path.emplace_back(waypoints[i] + d * (static_cast<double>(k) / n), heading);
  }
  if (!waypoints.empty()) {
    const double heading = path.empty() ? 0.0 : path.back().rotation();
    path.emplace_back(waypoints.back(), heading);
  }
  return path;
}

}  // namespace fleetmap::testing
