#include "shared/matching/scan_segments.h"

#include <cmath>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

constexpr double kDegree = M_PI / 180.0;

// Where beams from the origin, `step` apart from `first`, hit the line y = `wall_y`.
std::vector<Eigen::Vector2d> HitsOnWall(double wall_y, double first, double step, int count) {
  std::vector<Eigen::Vector2d> hits;
  for (int i = 0; i < count; ++i) {
    const double angle = first + i * step;
    hits.emplace_back(wall_y / std::tan(angle), wall_y);
  }
  return hits;
}

TEST(ScanSegmentsTest, SparseReturnsAlongAWallAreJoined) {
  // 1 degree beams hitting a wall 1 m to the side between ~4 and ~8 m ahead: 0.3-1.0 m apart.
  const std::vector<Eigen::Vector2d> hits = HitsOnWall(-1.0, -14.0 * kDegree, 1.0 * kDegree, 7);
  const std::vector<SurfaceElement> segments = JoinConsecutiveReturns(hits, Eigen::Vector2d::Zero(), ScanSegmentOptions());
  ASSERT_GE(segments.size(), 5u);
  for (const SurfaceElement& s : segments) {
    EXPECT_NEAR(s.centre.y(), -1.0, 1e-9);
    EXPECT_NEAR(std::abs(s.tangent.x()), 1.0, 1e-9);
    EXPECT_NEAR(s.extent_minus, s.extent_plus, 1e-12);
    EXPECT_GE(2.0 * s.extent_plus, ScanSegmentOptions().min_gap);
  }
}

TEST(ScanSegmentsTest, DepthJumpsDenseReturnsAndGapsInBearingAreNotJoined) {
  const ScanSegmentOptions options;
  const Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  // An object 2 m ahead, then the wall 5 m ahead, one degree apart.
  const std::vector<Eigen::Vector2d> jump = {{2.0, 0.0}, {5.0 * std::cos(kDegree), 5.0 * std::sin(kDegree)}};
  EXPECT_TRUE(JoinConsecutiveReturns(jump, origin, options).empty());
  // A wall straight ahead, 0.035 m between returns: the surface fit's job.
  const std::vector<Eigen::Vector2d> dense = {{2.0, 0.0}, {2.0, 0.035}};
  EXPECT_TRUE(JoinConsecutiveReturns(dense, origin, options).empty());
  // The same wall, but beams in between saw nothing (10 degrees apart).
  const std::vector<Eigen::Vector2d> skipped = HitsOnWall(-1.0, -20.0 * kDegree, 10.0 * kDegree, 2);
  EXPECT_TRUE(JoinConsecutiveReturns(skipped, origin, options).empty());
}

}  // namespace
}  // namespace fleetmap
