#ifndef FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_
#define FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_

#include "tests/support/test_support.h"

namespace fleetmap::testing {

// A 20 m x 15 m corridor ring, 2 m wide, with pillars along the outer wall so that the straight
// parts are not featureless: the loop every local SLAM backend is tested on.
SegmentWorld CorridorRing();

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_SLAM_SLAM_TEST_WORLDS_H_
