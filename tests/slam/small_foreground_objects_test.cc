#include "robot_agent/slam/small_foreground_objects.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "shared/core/laser_scan.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A 181-beam scan of `world` from the origin, as points in beam order (no-returns left out).
std::vector<Eigen::Vector2f> Points(const testing::SegmentWorld& world) {
  return ToPointsInRobotFrame(testing::SimulateScan(world, Rigid2d(), 181, static_cast<float>(-M_PI / 2),
                                                    static_cast<float>(M_PI / 180), 10.0f));
}

// How many points are flagged, and whether all of them lie inside the box [lo, hi].
struct Flagged {
  int count = 0;
  bool all_inside = true;
};
Flagged FlaggedIn(const std::vector<Eigen::Vector2f>& points, const Eigen::Vector2f& lo,
                  const Eigen::Vector2f& hi) {
  const std::vector<bool> small = SmallForegroundObjects(points, SmallForegroundObjectOptions());
  Flagged flagged;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!small[i]) continue;
    ++flagged.count;
    flagged.all_inside = flagged.all_inside && (points[i].array() >= lo.array() - 0.01f).all() &&
                         (points[i].array() <= hi.array() + 0.01f).all();
  }
  return flagged;
}

// A corridor 2.4 m wide with its end wall 8 m ahead, and a door on the left 3 m ahead, with the
// room behind it.
testing::SegmentWorld Corridor() {
  return {{Eigen::Vector2d(-1.0, -1.2), Eigen::Vector2d(8.0, -1.2)},
          {Eigen::Vector2d(-1.0, 1.2), Eigen::Vector2d(3.0, 1.2)},
          {Eigen::Vector2d(4.0, 1.2), Eigen::Vector2d(8.0, 1.2)},
          {Eigen::Vector2d(3.0, 1.2), Eigen::Vector2d(3.0, 5.0)},
          {Eigen::Vector2d(4.0, 1.2), Eigen::Vector2d(4.0, 5.0)},
          {Eigen::Vector2d(3.0, 5.0), Eigen::Vector2d(4.0, 5.0)},
          {Eigen::Vector2d(8.0, -1.2), Eigen::Vector2d(8.0, 1.2)}};
}

TEST(SmallForegroundObjectsTest, WallsJambsAndDoorsAreNotSmallObjects) {
  EXPECT_EQ(FlaggedIn(Points(Corridor()), {0, 0}, {0, 0}).count, 0);
}

TEST(SmallForegroundObjectsTest, ARobotAheadIsOneWhereverItStands) {
  for (const double y : {0.0, 0.6, -0.6}) {
    testing::SegmentWorld world = Corridor();
    testing::AddBox(Eigen::Vector2d(3.0, y - 0.2), Eigen::Vector2d(3.4, y + 0.2), &world);
    const Flagged flagged = FlaggedIn(Points(world), Eigen::Vector2f(3.0f, y - 0.2f), Eigen::Vector2f(3.4f, y + 0.2f));
    EXPECT_GE(flagged.count, 5) << "y " << y;
    EXPECT_TRUE(flagged.all_inside) << "y " << y;
  }
}

TEST(SmallForegroundObjectsTest, ABodyInFrontOfOpenSpaceIsOneAndALargeBoxIsNot) {
  // Nothing behind the body within range: its neighbours are beams that saw nothing.
  testing::SegmentWorld open;
  testing::AddBox(Eigen::Vector2d(2.0, -0.2), Eigen::Vector2d(2.4, 0.2), &open);
  EXPECT_GE(FlaggedIn(Points(open), {2.0f, -0.2f}, {2.4f, 0.2f}).count, 5);
  testing::SegmentWorld large = Corridor();
  testing::AddBox(Eigen::Vector2d(3.0, -0.6), Eigen::Vector2d(3.4, 0.6), &large);
  EXPECT_EQ(FlaggedIn(Points(large), {0, 0}, {0, 0}).count, 0);
}

// Two robots ahead are two objects, numbered in beam order; the walls are on none.
TEST(SmallForegroundObjectsTest, EachObjectHasItsOwnNumber) {
  testing::SegmentWorld world = Corridor();
  testing::AddBox(Eigen::Vector2d(3.0, -0.8), Eigen::Vector2d(3.4, -0.4), &world);
  testing::AddBox(Eigen::Vector2d(3.0, 0.4), Eigen::Vector2d(3.4, 0.8), &world);
  const std::vector<Eigen::Vector2f> points = Points(world);
  const std::vector<int> ids = SmallForegroundObjectIds(points, SmallForegroundObjectOptions());
  const std::vector<bool> small = SmallForegroundObjects(points, SmallForegroundObjectOptions());
  ASSERT_EQ(ids.size(), points.size());
  int right = 0, left = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(ids[i] >= 0, small[i]);
    if (ids[i] < 0) continue;
    EXPECT_EQ(ids[i], points[i].y() < 0.0f ? 0 : 1) << "return " << i;  // the right one first
    (points[i].y() < 0.0f ? right : left) += 1;
  }
  EXPECT_GE(right, 5);
  EXPECT_GE(left, 5);
}

}  // namespace
}  // namespace fleetmap
