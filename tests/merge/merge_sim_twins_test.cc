// The bench's twin diagnostic (map_server/bench/merge_sim_twins.h) on maps with known frames.
#include "map_server/bench/merge_sim_twins.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

constexpr double kResolution = 0.2;  // as the bench counts at the true anchors

std::vector<Rigid2d> OfficeRooms() {
  return {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0),    Rigid2d(10, 6, 0),
          Rigid2d(10, 10, 0), Rigid2d(10, 1.5, 0), Rigid2d(16, 6, 0)};
}

std::vector<Rigid2d> BothOffices() {
  std::vector<Rigid2d> poses = OfficeRooms();
  for (const Rigid2d& p : OfficeRooms()) poses.push_back(testing::TwinOfficesHalfTurn() * p);
  return poses;
}

// Robot a scanned from `a`, robot b from `b`, both maps in the world frame (their true
// anchors), seen as the bench's PairOverlaps sees them.
std::optional<PairTwin> TwinOf(const testing::SegmentWorld& world, const std::vector<Rigid2d>& a,
                               const std::vector<Rigid2d>& b) {
  const MergeEngineOptions defaults;
  MatchTargetOptions options = defaults.match;
  options.grid.resolution = kResolution;
  options.grid.sigma = 0.0;
  std::vector<std::unique_ptr<MatchTarget>> targets;
  std::vector<MatchSource> sources;
  for (const std::vector<Rigid2d>* poses : {&a, &b}) {
    const OccupancyGrid grid = testing::GridFromScans(world, *poses, Rigid2d(), kResolution);
    targets.push_back(std::make_unique<MatchTarget>(grid, options));
    sources.push_back(MakeMatchSource(grid, Rigid2d(), options));
  }
  std::vector<Rigid2d> both = a;
  both.insert(both.end(), b.begin(), b.end());
  const OccupancyGrid all = testing::GridFromScans(world, both, Rigid2d(), kResolution);
  const std::vector<std::optional<PairTwin>> twins =
      PairTwins(targets, sources, MatchTarget(all, options),
                MakeMatchSource(all, Rigid2d(), options), defaults);
  EXPECT_EQ(twins.size(), 1u);
  return twins.empty() ? std::nullopt : twins.front();
}

// a saw both offices, b only the left one: b moved by the half turn lands in the right office,
// where a's map looks as b's does, and crosses none of a's seen-free space. Nothing in the two
// maps tells that twin from the truth.
TEST(MergeSimTwinsTest, InTwinOfficesTheHalfTurnedTwinStands) {
  const std::vector<Rigid2d> rooms = OfficeRooms();
  const std::vector<Rigid2d> left(rooms.begin(), rooms.begin() + 3);
  const std::optional<PairTwin> twin = TwinOf(testing::TwinOffices(), BothOffices(), left);
  ASSERT_TRUE(twin.has_value());
  EXPECT_FALSE(twin->ruled_out);
  EXPECT_NEAR(std::abs(NormalizeAngle(twin->move.rotation())), M_PI, 0.05);
  EXPECT_GT(twin->shift, 10.0);
  EXPECT_GE(twin->score_ratio, 0.85);
  EXPECT_LT(twin->crossings, 20);
}

// The office alone has no symmetry: the truth has no twin.
TEST(MergeSimTwinsTest, TheOfficeAloneHasNoTwin) {
  const std::vector<Rigid2d> rooms = OfficeRooms();
  const std::vector<Rigid2d> left(rooms.begin(), rooms.begin() + 3);
  EXPECT_FALSE(TwinOf(testing::OfficeWorld(), OfficeRooms(), left).has_value());
}

}  // namespace
}  // namespace fleetmap
