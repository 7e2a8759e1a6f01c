#ifndef FLEETMAP_TESTS_MERGE_MERGE_TEST_WORLDS_H_
#define FLEETMAP_TESTS_MERGE_MERGE_TEST_WORLDS_H_

// Synthetic worlds, grids and submaps with known frames for the merge engine's tests.

#include <string>
#include <vector>

#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"
#include "shared/core/submap.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

// An office-like floor (about 20 m x 12 m) with rooms and clutter: no symmetry.
SegmentWorld OfficeWorld();
// The office and beside it the office turned half round about (20, 6) (TwinOfficesHalfTurn):
// every wall of one is a wall of the other turned round, as in the simulator's department. A
// door in the wall they share (x = 20, y = 5-7) joins them. With `crates`, the office (not its
// turned twin) has a crate in its middle room and one in its right room, out of the robots'
// way: then the twins differ, but only a little.
SegmentWorld TwinOffices(bool crates = false);
Rigid2d TwinOfficesHalfTurn();
// A long straight corridor (walls at y = 0 and y = 2, from x = 0 to 30): translation-symmetric.
SegmentWorld CorridorWorld();

// A grid (in frame F) from 360-degree scans taken at `robot_in_world` poses, where F sits at
// `frame_in_world`: the grid a robot would build in its own frame.
OccupancyGrid GridFromScans(const SegmentWorld& world, const std::vector<Rigid2d>& robot_in_world,
                            const Rigid2d& frame_in_world, double resolution = 0.05);

// Submaps of one robot driving `path` (world poses, one scan per pose, `scans_per_submap` per
// submap), its local frame sitting at `local_in_world`; pose timestamps are index * dt.
std::vector<Submap> MakeSubmaps(const std::string& robot, const SegmentWorld& world,
                                const std::vector<Rigid2d>& path, const Rigid2d& local_in_world,
                                int scans_per_submap, double dt = 0.5);
// The robot's trajectory in its local frame for the same path.
Trajectory MakeTrajectory(const std::vector<Rigid2d>& path, const Rigid2d& local_in_world,
                          double dt = 0.5);

// A path through waypoints, one pose every `step` metres, heading along the path.
std::vector<Rigid2d> PathThrough(const std::vector<Eigen::Vector2d>& waypoints, double step);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_MERGE_MERGE_TEST_WORLDS_H_
