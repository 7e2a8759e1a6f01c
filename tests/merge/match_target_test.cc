#include "map_server/merge/match_target.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

class MatchTargetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    world_ = testing::OfficeWorld();
    // The target robot explored the left two rooms; its frame is the world frame.
    target_grid_ = testing::GridFromScans(
        world_, {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0), Rigid2d(10, 6, 0), Rigid2d(10, 10, 0),
                 Rigid2d(10, 1.5, 0)},
        Rigid2d());
  }
  testing::SegmentWorld world_;
  OccupancyGrid target_grid_;
  MatchTargetOptions options_;
};

// The source submap saw the middle room from a frame at any heading; global search (whole map,
// full circle) must recover the frame within 3 cm and 0.3 degrees.
TEST_F(MatchTargetTest, GlobalSearchRecoversAnyHeading) {
  const MatchTarget target(target_grid_, options_);
  for (double heading : {-M_PI, -2.5, -1.2, -0.3, 0.0, 0.7, 1.9, 3.0}) {
    const Rigid2d source_in_world(9.7, 5.6, heading);
    const OccupancyGrid source_grid = testing::GridFromScans(
        world_, {Rigid2d(9.5, 5.5, 0.3), Rigid2d(10.5, 6.5, 0.3)}, source_in_world);
    const MatchSource source = MakeMatchSource(source_grid, Rigid2d(), options_);
    SearchWindow window;
    window.center = Rigid2d(0.5 * (target.min_corner() + target.max_corner()), 0.0);
    window.linear_half_extent = 0.5 * (target.max_corner() - target.min_corner());
    window.angular_half_extent = M_PI;
    const MatchResult result = target.Match(source, window, MatchGates());
    EXPECT_TRUE(result.accepted) << result.reason;
    EXPECT_THAT(result.pose, IsNearPose(source_in_world, 0.03, 0.3 * M_PI / 180))
        << "heading " << heading << ": " << result.reason;
  }
}

// A wrong prior window that does not contain the true pose must not produce an accepted match.
TEST_F(MatchTargetTest, WrongWindowIsNotAccepted) {
  const MatchTarget target(target_grid_, options_);
  const Rigid2d source_in_world(9.7, 5.6, 1.0);
  const OccupancyGrid source_grid =
      testing::GridFromScans(world_, {Rigid2d(9.5, 5.5, 0.3)}, source_in_world);
  const MatchSource source = MakeMatchSource(source_grid, Rigid2d(), options_);
  SearchWindow window;
  window.center = Rigid2d(4.0, 6.0, 1.0);
  window.linear_half_extent = Eigen::Vector2d(0.5, 0.5);
  window.angular_half_extent = M_PI;
  EXPECT_FALSE(target.Match(source, window, MatchGates()).accepted);
}

// The source robot mapped the left room and the middle room beyond the door; the target only
// the left room (as when a camera sees a robot farther than the laser maps). Around the known
// position, with the heading unknown, a mean score over all source points can never reach the
// gate (the unseen half scores 0); judged on the overlap, the true pose is found and accepted.
TEST(MatchTargetOverlapTest, KnownPositionPartialOverlapIsJudgedOnTheOverlap) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MatchTargetOptions options;
  const MatchTarget target(
      testing::GridFromScans(world, {Rigid2d(2, 6, 0), Rigid2d(4, 8, 0), Rigid2d(5, 4, 0)}, Rigid2d()), options);
  MatchGates gates;
  gates.min_score = 0.6;
  gates.min_overlap = 0.3;
  gates.min_inlier_fraction = 0.6;
  for (double heading : {-2.0, 0.5, 2.9}) {
    const Rigid2d source_in_world(6.0, 6.0, heading);
    const OccupancyGrid source_grid = testing::GridFromScans(
        world, {Rigid2d(5, 6, 0), Rigid2d(9, 6, 0), Rigid2d(10, 9.5, 0), Rigid2d(11, 4, 0)}, source_in_world);
    const MatchSource source = MakeMatchSource(source_grid, Rigid2d(), options);
    SearchWindow window;
    window.center = Rigid2d(Eigen::Vector2d(6.05, 5.95), 0.0);
    window.linear_half_extent = Eigen::Vector2d::Constant(0.15);
    window.angular_half_extent = M_PI;
    gates.judge_overlap_only = false;
    const MatchResult all_points = target.Match(source, window, gates);
    EXPECT_FALSE(all_points.accepted) << all_points.reason;
    gates.judge_overlap_only = true;
    const MatchResult result = target.Match(source, window, gates);
    EXPECT_LT(result.overlap, 0.6) << result.reason;
    EXPECT_TRUE(result.accepted) << result.reason;
    EXPECT_THAT(result.pose, IsNearPose(source_in_world, 0.03, 0.3 * M_PI / 180))
        << "heading " << heading << ": " << result.reason;
    // The same source around a wrong position (1 m off) is not accepted.
    window.center = Rigid2d(Eigen::Vector2d(5.0, 6.0), 0.0);
    const MatchResult wrong = target.Match(source, window, gates);
    EXPECT_FALSE(wrong.accepted) << wrong.reason;
  }
}

// The corridor driven end to end (the target), a stretch of it seen from `source_in_world`,
// and a window over the whole target.
struct CorridorCase {
  std::unique_ptr<MatchTarget> target;
  MatchSource source;
  SearchWindow window;
};

CorridorCase MakeCorridorCase(const Rigid2d& source_in_world) {
  const testing::SegmentWorld world = testing::CorridorWorld();
  std::vector<Rigid2d> poses;
  for (double x = 2; x <= 28; x += 2) poses.emplace_back(x, 1, 0);
  MatchTargetOptions options;
  CorridorCase c;
  c.target =
      std::make_unique<MatchTarget>(testing::GridFromScans(world, poses, Rigid2d()), options);
  const OccupancyGrid source_grid =
      testing::GridFromScans(world, {Rigid2d(13, 1, 0), Rigid2d(15, 1, 0)}, source_in_world);
  c.source = MakeMatchSource(source_grid, Rigid2d(), options);
  c.window.center = Rigid2d(0.5 * (c.target->min_corner() + c.target->max_corner()), 0.0);
  c.window.linear_half_extent = 0.5 * (c.target->max_corner() - c.target->min_corner());
  return c;
}

// A stretch of straight corridor matches equally well anywhere along the corridor: ambiguous.
TEST(MatchTargetCorridorTest, CorridorIsAmbiguous) {
  const CorridorCase c = MakeCorridorCase(Rigid2d(14.0, 1.0, 0.4));
  const MatchResult result = c.target->Match(c.source, c.window, MatchGates());
  EXPECT_TRUE(result.found);
  EXPECT_FALSE(result.accepted) << result.reason;
  EXPECT_GT(result.ambiguity, 0.85);
}

// Walls seen through: none at the true pose, many when the source is pushed into the rooms the
// target saw empty, none where the target saw nothing.
TEST_F(MatchTargetTest, CountsSourceWallsInsideSpaceTheTargetSawFree) {
  const MatchTarget target(target_grid_, options_);
  const OccupancyGrid source_grid =
      testing::GridFromScans(world_, {Rigid2d(3.5, 6, 0), Rigid2d(10, 6, 0)}, Rigid2d());
  const MatchSource source = MakeMatchSource(source_grid, Rigid2d(), options_);
  ASSERT_GT(source.fine.size(), 200u);
  EXPECT_LE(target.ContradictionsAt(source.fine, Rigid2d()), 5);
  EXPECT_GE(target.ContradictionsAt(source.fine, Rigid2d(1.5, 1.5, 0.0)), 100);
  EXPECT_EQ(target.ContradictionsAt(source.fine, Rigid2d(100.0, 0.0, 0.0)), 0);
}

// A map that drifted: the right part of the source's walls stands 0.4 m off. Rigidly placed,
// they cross the target's seen-free space; each tile moved on its own by up to 0.5 m, they do
// not. Walls pushed 1.5 m into the rooms still cross it, and a window of 0 is the rigid count.
// Where tiles may move only a little near the centroid, a map off as a whole stays counted.
TEST_F(MatchTargetTest, CountsWallsSeenThroughWithEachTileFittedOnItsOwn) {
  const MatchTarget target(target_grid_, options_);
  const OccupancyGrid source_grid =
      testing::GridFromScans(world_, {Rigid2d(3.5, 6, 0), Rigid2d(10, 6, 0)}, Rigid2d());
  std::vector<Eigen::Vector2d> drifted = MakeMatchSource(source_grid, Rigid2d(), options_).fine;
  for (Eigen::Vector2d& p : drifted) {
    if (p.x() >= 8.0) p += Eigen::Vector2d(0.0, 0.4);
  }
  const int rigid = target.ContradictionsAt(drifted, Rigid2d());
  ASSERT_GE(rigid, 20);
  EXPECT_EQ(target.LocallyFittedContradictionsAt(drifted, Rigid2d(), 4.0, 0.0, 1.0), rigid);
  EXPECT_LE(target.LocallyFittedContradictionsAt(drifted, Rigid2d(), 4.0, 0.5, 1.0), 5);
  const Rigid2d pushed(1.5, 1.5, 0.0);
  EXPECT_GE(target.LocallyFittedContradictionsAt(drifted, pushed, 4.0, 0.5, 1.0),
            target.ContradictionsAt(drifted, pushed) / 2);
  EXPECT_GE(target.LocallyFittedContradictionsAt(drifted, pushed, 4.0, 0.5, 1.0), 50);
  // Tiles move at most 1 cm per metre from the points' centroid: the drifted part, a few metres
  // out, keeps most of its crossings, and so does the whole map placed 0.4 m off.
  EXPECT_GE(target.LocallyFittedContradictionsAt(drifted, Rigid2d(), 4.0, 0.5, 0.01), rigid / 2);
  const Rigid2d off(0.0, 0.4, 0.0);
  EXPECT_GE(target.LocallyFittedContradictionsAt(drifted, off, 4.0, 0.5, 0.01),
            target.ContradictionsAt(drifted, off) / 2);
  EXPECT_GE(target.ContradictionsAt(drifted, off), 20);
}

// A source reaching past what the target saw keeps only the points on the target's observed
// cells, each with its own normal; shifted far away from the target, none.
TEST_F(MatchTargetTest, KeepsOnlyThePointsTheTargetSaw) {
  const OccupancyGrid left_room = testing::GridFromScans(world_, {Rigid2d(3.5, 6, 0)}, Rigid2d());
  const MatchSource whole = MakeMatchSource(target_grid_, Rigid2d(), options_);
  MatchSource seen = whole;
  KeepPointsSeenBy(left_room, Rigid2d(), &seen);
  ASSERT_GT(seen.fine.size(), 50u);
  EXPECT_LT(seen.fine.size(), whole.fine.size());
  EXPECT_LT(seen.coarse.size(), whole.coarse.size());
  ASSERT_EQ(seen.fine_normals.size(), seen.fine.size());
  ASSERT_EQ(seen.coarse_normals.size(), seen.coarse.size());
  for (size_t i = 0; i < seen.fine.size(); ++i) {
    EXPECT_TRUE(left_room.IsKnown(left_room.CellAt(seen.fine[i])));
    const size_t j = static_cast<size_t>(
        std::find(whole.fine.begin(), whole.fine.end(), seen.fine[i]) - whole.fine.begin());
    ASSERT_LT(j, whole.fine.size());
    EXPECT_EQ(seen.fine_normals[i], whole.fine_normals[j]);
  }
  MatchSource far = whole;
  KeepPointsSeenBy(left_room, Rigid2d(100.0, 0.0, 0.0), &far);
  EXPECT_TRUE(far.fine.empty());
  EXPECT_TRUE(far.coarse.empty());
}

// Along a corridor every shift fits: each zone excluded rules out one more of them, and the
// peaks come best first, the same poses a fresh search outside the same zones finds.
TEST(MatchTargetCorridorTest, PeaksOutsideSkipsEveryZoneBestFirst) {
  const CorridorCase c = MakeCorridorCase(Rigid2d());
  const ExclusionZone first{Rigid2d(), 0.5, 0.26};
  std::vector<ExclusionZone> zones = {first};
  PeakSearch peaks = c.target->PeaksOutside(c.source, c.window, 0.3, zones);
  double last_score = 2.0;
  for (int i = 0; i < 6; ++i) {
    const auto found = peaks.Next();
    ASSERT_TRUE(found) << "peak " << i;
    EXPECT_LE(found->score, last_score);
    last_score = found->score;
    for (const ExclusionZone& zone : zones) {
      const Rigid2d apart = zone.center.inverse() * found->pose;
      EXPECT_TRUE(apart.translation().norm() >= zone.linear ||
                  std::abs(apart.rotation()) >= zone.angular)
          << "pose " << found->pose << " inside zone " << zone.center;
    }
    // A search started afresh outside the same zones finds a peak scoring the same.
    const auto fresh = c.target->PeaksOutside(c.source, c.window, 0.3, zones).Next();
    ASSERT_TRUE(fresh);
    EXPECT_FLOAT_EQ(fresh->score, found->score);
    zones.push_back(ExclusionZone{found->pose, 0.5, 0.26});
    peaks.Exclude(zones.back());
  }
}

}  // namespace
}  // namespace fleetmap
