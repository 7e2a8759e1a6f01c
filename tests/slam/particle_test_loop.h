#ifndef FLEETMAP_TESTS_SLAM_PARTICLE_TEST_LOOP_H_
#define FLEETMAP_TESTS_SLAM_PARTICLE_TEST_LOOP_H_

#include <functional>
#include <vector>

#include "robot_agent/slam/local_slam.h"
#include "robot_agent/slam/particle_slam.h"
#include "shared/core/rigid2d.h"
#include "tests/slam/slam_test_worlds.h"

// The simulated loop the particle backends' tests drive: the corridor ring of
// slam_test_worlds.h (and its NoisyOdometry), 0.1 s per scan.
namespace fleetmap::testing {

// One lap and a bit along the ring's centre line (so the end revisits the start): 0.1 m steps,
// turning on the spot at the corners.
std::vector<Rigid2d> LoopPoses();
// Runs a backend over the simulated loop (scans with 0.5 cm range noise); `after_scan`, when
// set, runs after every scan.
void RunLoop(LocalSlam* slam, const std::vector<Rigid2d>& truth, const std::vector<Rigid2d>& odometry,
             const std::function<void()>& after_scan = nullptr);
// The RBPF with 10 particles and 10 m returns.
ParticleSlamOptions SmallRbpf(unsigned seed, int threads);
// Distance between the backend's current pose and the loop's true end (start frame).
double EndError(const LocalSlam& slam, const std::vector<Rigid2d>& truth);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_SLAM_PARTICLE_TEST_LOOP_H_
