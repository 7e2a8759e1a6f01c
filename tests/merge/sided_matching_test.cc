// Matching maps that saw the same thick walls from opposite sides (SidedDistanceField and the
// sided refinement of MatchTarget).
#include <gtest/gtest.h>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/match_target.h"
#include "map_server/merge/sided_distance_field.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;
using testing::SegmentWorld;

// A corridor (y in [0, 2.4]) with 0.2 m thick fins on both walls every 4 m: a robot driving east
// with a forward laser sees only their west faces, one driving west only their east faces.
SegmentWorld FinnedCorridor() {
  SegmentWorld world = testing::BoxWorld(Eigen::Vector2d(0, 0), Eigen::Vector2d(24, 2.4));
  for (double x = 3.0; x < 22.0; x += 4.0) {
    testing::AddBox(Eigen::Vector2d(x, 0.0), Eigen::Vector2d(x + 0.2, 0.7), &world);
    testing::AddBox(Eigen::Vector2d(x + 2.0, 1.7), Eigen::Vector2d(x + 2.2, 2.4), &world);
  }
  return world;
}

// The map (in frame F at `frame_in_world`) of a robot driving from x0 to x1 at y = 1.2, facing
// its direction of travel, a 180-degree scan every 0.25 m.
OccupancyGrid DriveMap(const SegmentWorld& world, double x0, double x1,
                       const Rigid2d& frame_in_world) {
  OccupancyGrid grid;
  const double step = x1 > x0 ? 0.25 : -0.25;
  const double heading = x1 > x0 ? 0.0 : M_PI;
  for (double x = x0; step > 0 ? x <= x1 : x >= x1; x += step) {
    const Rigid2d pose(x, 1.2, heading);
    grid.InsertScan(testing::SimulateScan(world, pose), frame_in_world.inverse() * pose);
  }
  return grid;
}

TEST(WallNormalsTest, PointTowardsTheSideTheWallWasSeenFrom) {
  const SegmentWorld world = FinnedCorridor();
  const OccupancyGrid grid = DriveMap(world, 1.0, 22.0, Rigid2d());
  const float occupied = 0.4f, free = -0.4f;
  const std::vector<Eigen::Vector2d> points = OccupiedPoints(grid, occupied);
  const std::vector<Eigen::Vector2d> normals = WallNormals(grid, occupied, free);
  ASSERT_EQ(points.size(), normals.size());
  int west_faces = 0, east_faces = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    // The west face of the south fin at x = 11 (seen from the west: its normal points west).
    if (std::abs(p.x() - 11.0) < 0.05 && p.y() > 0.1 && p.y() < 0.6) {
      ++west_faces;
      EXPECT_LT(normals[i].x(), -0.7) << p.transpose() << ": " << normals[i].transpose();
    }
    // The fin's east face was never seen.
    east_faces += std::abs(p.x() - 11.2) < 0.03 && p.y() > 0.1 && p.y() < 0.6;
  }
  EXPECT_GT(west_faces, 4);
  EXPECT_EQ(east_faces, 0);
}

TEST(SidedDistanceFieldTest, FindsOnlyWallsSeenFromTheSameSide) {
  const SegmentWorld world = FinnedCorridor();
  const OccupancyGrid westward = DriveMap(world, 22.0, 1.0, Rigid2d());  // sees east faces
  const float occupied = 0.4f, free = -0.4f;
  LikelihoodFieldOptions options;
  options.occupied_probability = LogOddsToProbability(occupied);
  options.max_distance = 0.3;
  const auto plain = std::make_shared<const LikelihoodField>(westward, options);
  const SidedDistanceField sided(westward, Box2d{Eigen::Vector2d(0, 0), Eigen::Vector2d(24, 2.4)},
                                 occupied, free, plain);
  // On the west face of the fin at x = 11, 0.2 m west of the east face the map holds (and over
  // 0.3 m from the corners the map saw from the west).
  const Eigen::Vector2d on_west_face(10.975, 0.35);
  Eigen::Vector2d gradient;
  EXPECT_NEAR(plain->DistanceAndGradient(on_west_face, &gradient), 0.2, 0.03);
  // Seen from the west (normal pointing west), that face has no counterpart within reach...
  EXPECT_GE(sided.DistanceAndGradient(
                on_west_face, SidedDistanceField::SectorOf(Eigen::Vector2d(-1, 0)), &gradient),
            0.29);
  // ...while a point on the east face, seen from the east, lies on the map's wall.
  EXPECT_LT(
      sided.DistanceAndGradient(Eigen::Vector2d(11.225, 0.35),
                                SidedDistanceField::SectorOf(Eigen::Vector2d(1, 0)), &gradient),
      0.03);
  EXPECT_EQ(SidedDistanceField::SectorOf(Eigen::Vector2d::Zero()), -1);
}

// Two robots drove the finned corridor in opposite directions. Plain point-to-wall distances
// snap each fin face onto the opposite face of the same fin and slide the match along the
// corridor by about the fin thickness; the sided refinement keeps it within 3 cm.
TEST(SidedMatchingTest, OppositeDirectionsMatchWithoutSliding) {
  const SegmentWorld world = FinnedCorridor();
  MatchTargetOptions options;
  const OccupancyGrid target_grid = DriveMap(world, 1.0, 22.0, Rigid2d());
  const MatchTarget target(target_grid, options);
  for (const Rigid2d& source_in_world : {Rigid2d(12.0, 1.0, 0.3), Rigid2d(9.0, 1.5, -2.0)}) {
    const OccupancyGrid source_grid = DriveMap(world, 15.0, 6.0, source_in_world);
    const MatchSource source = MakeMatchSource(source_grid, Rigid2d(), options);
    SearchWindow window;
    window.center = Rigid2d(source_in_world.translation() + Eigen::Vector2d(0.1, -0.1),
                            source_in_world.rotation() + 0.02);
    window.linear_half_extent = Eigen::Vector2d::Constant(0.4);
    window.angular_half_extent = 0.1;
    const MatchResult result = target.Match(source, window, MatchGates());
    EXPECT_TRUE(result.found) << result.reason;
    EXPECT_THAT(result.pose, IsNearPose(source_in_world, 0.03, 0.3 * M_PI / 180)) << result.reason;

    // The situation the test is about: refined from the truth on plain distances (every source
    // point without a side), the match slides away.
    LikelihoodFieldOptions field_options;
    field_options.occupied_probability = LogOddsToProbability(options.grid.occupied_log_odds);
    field_options.max_distance = options.fine_field_max_distance;
    const auto plain = std::make_shared<const LikelihoodField>(target_grid, field_options);
    const Box2d everywhere{Eigen::Vector2d(-1, -1), Eigen::Vector2d(25, 4)};
    const SidedDistanceField field(target_grid, everywhere, options.grid.occupied_log_odds,
                                   options.grid.free_log_odds, plain);
    const std::vector<Eigen::Vector2d> no_sides(source.fine.size(), Eigen::Vector2d::Zero());
    const RefinedPose slid =
        RefineSidedPose(field, {source.fine, no_sides}, {source.fine, no_sides}, source_in_world,
                        everywhere, options.refine);
    EXPECT_GT((slid.pose.translation() - source_in_world.translation()).norm(), 0.08);
  }
}

}  // namespace
}  // namespace fleetmap
