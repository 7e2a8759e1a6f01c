// The refinement of a correlative match (RefineSidedPose): points far from every wall, such as
// another robot's body mapped where it passed, must not pull the match.
#include "map_server/merge/pose_refiner.h"

#include <gtest/gtest.h>

#include <memory>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/match_target.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

// A room with a crate, mapped exactly from a few poses: the target. The source is the same map
// in the same frame (the true pose is the identity) plus a robot's body: an arc of points 0.2 m
// from the north wall along its eastern half, a wall point's pull away from any wall.
struct RoomWithABody {
  OccupancyGrid target;
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2d> no_sides;
};

RoomWithABody MakeRoomWithABody() {
  testing::SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(0, 0), Eigen::Vector2d(10, 4));
  testing::AddBox(Eigen::Vector2d(3, 1), Eigen::Vector2d(3.6, 1.5), &world);
  RoomWithABody room;
  for (const Rigid2d& pose : {Rigid2d(2, 2, 0), Rigid2d(5, 2.5, 1.0), Rigid2d(8, 2, 3.0)}) {
    room.target.InsertScan(testing::SimulateScan(world, pose), pose);
  }
  const MatchTargetOptions options;
  room.points = OccupiedPoints(room.target, options.grid.occupied_log_odds);
  const size_t walls = room.points.size();
  for (int i = 0; i < static_cast<int>(walls) / 3; ++i) {
    room.points.emplace_back(5.5 + 4.0 * i / (walls / 3.0), 4.0 - 0.2 - 0.01 * (i % 3));
  }
  room.no_sides.assign(room.points.size(), Eigen::Vector2d::Zero());
  return room;
}

RefinedPose Refine(const RoomWithABody& room, double max_pull_distance) {
  const MatchTargetOptions options;
  LikelihoodFieldOptions field_options;
  field_options.occupied_probability = LogOddsToProbability(options.grid.occupied_log_odds);
  field_options.max_distance = options.fine_field_max_distance;
  const auto plain = std::make_shared<const LikelihoodField>(room.target, field_options);
  const Box2d everywhere{Eigen::Vector2d(-1, -1), Eigen::Vector2d(11, 5)};
  const SidedDistanceField field(room.target, everywhere, options.grid.occupied_log_odds,
                                 options.grid.free_log_odds, plain);
  PoseRefinerOptions refine = options.refine;
  refine.max_pull_distance = max_pull_distance;
  return RefineSidedPose(field, {room.points, room.no_sides}, {room.points, room.no_sides},
                         Rigid2d(), everywhere, refine);
}

TEST(PoseRefinerTest, ABodyAwayFromTheWallsDoesNotPullTheMatch) {
  const RefinedPose refined = Refine(MakeRoomWithABody(), PoseRefinerOptions().max_pull_distance);
  EXPECT_LT(refined.pose.translation().norm(), 0.001) << refined.pose;
  EXPECT_LT(std::abs(refined.pose.rotation()), 0.0002) << refined.pose;
}

// Without the limit the body turns the room (0.17 deg when written), so the test above can fail.
TEST(PoseRefinerTest, WithoutTheLimitTheBodyPullsTheMatch) {
  const RefinedPose refined = Refine(MakeRoomWithABody(), 0.0);
  EXPECT_GT(std::abs(refined.pose.rotation()), 0.001) << refined.pose;
}

}  // namespace
}  // namespace fleetmap
