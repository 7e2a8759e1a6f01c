#ifndef FLEETMAP_TESTS_MATCHING_MATCHING_WORLDS_H_
#define FLEETMAP_TESTS_MATCHING_MATCHING_WORLDS_H_

#include <vector>

#include <Eigen/Core>

#include "shared/matching/match_grid.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

// A 10 m x 8 m room with three boxes of different sizes: no symmetry a matcher could confuse.
inline SegmentWorld FurnishedRoom() {
  SegmentWorld world = BoxWorld(Eigen::Vector2d(-5.0, -4.0), Eigen::Vector2d(5.0, 4.0));
  AddBox(Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(1.6, 2.2), &world);
  AddBox(Eigen::Vector2d(-3.0, -2.5), Eigen::Vector2d(-2.2, -2.1), &world);
  AddBox(Eigen::Vector2d(2.5, -3.0), Eigen::Vector2d(3.5, -2.0), &world);
  return world;
}

// Points along every segment, `spacing` apart: the ideal map of the world.
inline std::vector<Eigen::Vector2d> SampleWorld(const SegmentWorld& world, double spacing) {
  std::vector<Eigen::Vector2d> points;
  for (const Segment& s : world) {
    const double length = (s.b - s.a).norm();
    const int n = static_cast<int>(length / spacing) + 1;
    for (int i = 0; i <= n; ++i) points.push_back(s.a + (s.b - s.a) * (static_cast<double>(i) / n));
  }
  return points;
}

inline MatchGrid WorldGrid(const SegmentWorld& world, double resolution = 0.05,
                           double max_distance = 0.3) {
  MatchGridOptions options;
  options.resolution = resolution;
  options.max_distance = max_distance;
  return MatchGrid::FromPoints(SampleWorld(world, 0.01), options);
}

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_MATCHING_MATCHING_WORLDS_H_
