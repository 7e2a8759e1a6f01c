#ifndef FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_
#define FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_

#include <vector>

#include "shared/core/rigid2d.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

// A 20 m x 15 m corridor ring, 2 m wide, with pillars along the outer wall so that the straight
// parts are not featureless: the loop every local SLAM backend is tested on.
SegmentWorld CorridorRing();

// Poses along the corners' polyline, starting heading along +x: 0.1 m steps on the straights,
// and after each straight (but the last unless `turn_after_last`) a 90 degree left turn on the
// spot in 9 degree steps.
std::vector<Rigid2d> PathPoses(const std::vector<Eigen::Vector2d>& corners, bool turn_after_last);

// Odometry along `truth` with a systematic heading drift (0.5 degree per metre) and random
// noise (3 % of each step's length, 1 % sideways, 2 % of each turn).
std::vector<Rigid2d> NoisyOdometry(const std::vector<Rigid2d>& truth, unsigned seed);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_
