// Which small objects the local map says moved since the last scan, asked at a predicted pose.
#include "robot_agent/slam/local_match_map.h"

#include <vector>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

// The back of a 0.4 m wide body right ahead at `x`, in beam order; the first `other` returns
// lie at `other_x` instead (a face that is partly somewhere else).
std::vector<Eigen::Vector2f> BodyBack(float x, int other = 0, float other_x = 0.0f) {
  std::vector<Eigen::Vector2f> points;
  for (int i = 0; i <= 8; ++i) points.emplace_back(i < other ? other_x : x, -0.2f + 0.05f * i);
  return points;
}

int Count(const std::vector<bool>& flags) {
  int n = 0;
  for (bool f : flags) n += f ? 1 : 0;
  return n;
}

// A robot drives 8 cm per scan with another one 3 m ahead at its speed: at the pose odometry
// predicts, none of the other robot's returns lies where the last scan saw it.
TEST(LocalMatchMapTest, ARobotDrivingAheadMovedAndAStillOneDidNot) {
  LocalMatchMap map{LocalMatchMapOptions()};
  map.Track(BodyBack(3.0f), Rigid2d());
  const Rigid2d predicted(Eigen::Vector2d(0.08, 0.0), 0.0);
  EXPECT_EQ(Count(map.Moved(BodyBack(3.0f), predicted)), 9);
  // Standing still, 3.08 m from the origin: seen from the new pose, 3 m ahead.
  EXPECT_EQ(Count(map.Moved(BodyBack(3.0f - 0.08f), predicted)), 0);
}

// A door jamb coming out from behind a wall's corner: most of its face is new, but the part seen
// before is still there, so it did not move.
TEST(LocalMatchMapTest, AnObjectShowingANewPartAndAnOldOneDidNotMove) {
  LocalMatchMap map{LocalMatchMapOptions()};
  map.Track(BodyBack(3.0f), Rigid2d());
  EXPECT_EQ(Count(map.Moved(BodyBack(3.2f, 2, 3.0f), Rigid2d())), 0);
}

TEST(LocalMatchMapTest, AskingRecordsNothing) {
  LocalMatchMap map{LocalMatchMapOptions()};
  map.Track(BodyBack(3.0f), Rigid2d());
  map.Moved(BodyBack(2.5f), Rigid2d());
  EXPECT_EQ(Count(map.Moved(BodyBack(3.0f), Rigid2d())), 0);
  EXPECT_EQ(Count(map.Track(BodyBack(3.0f), Rigid2d())), 9);
}

}  // namespace
}  // namespace fleetmap
