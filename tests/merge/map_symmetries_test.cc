#include "map_server/merge/map_symmetries.h"

#include <gtest/gtest.h>

#include <vector>

#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

// The moves found in a map scanned from `poses` (world frame = map frame), at the resolution
// the merge engine's whole-map check uses.
std::vector<Rigid2d> SymmetriesOf(const testing::SegmentWorld& world,
                                  const std::vector<Rigid2d>& poses) {
  MatchTargetOptions options;
  options.grid.resolution = 0.2;
  options.grid.sigma = 0.0;
  const OccupancyGrid grid = testing::GridFromScans(world, poses, Rigid2d(), 0.2);
  const MatchTarget target(grid, options);
  const MatchSource source = MakeMatchSource(grid, Rigid2d(), options);
  return MapSymmetries(target, source, source.fine, MapSymmetryOptions());
}

std::vector<Rigid2d> AllSixRooms() {
  std::vector<Rigid2d> poses = {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0),   Rigid2d(10, 6, 0),
                                Rigid2d(10, 10, 0), Rigid2d(10, 1.5, 0), Rigid2d(16, 6, 0)};
  const size_t office = poses.size();
  for (size_t i = 0; i < office; ++i) poses.push_back(testing::TwinOfficesHalfTurn() * poses[i]);
  return poses;
}

// The office and its twin turned half round: the map fits itself turned round about (20, 6).
TEST(MapSymmetriesTest, TwinOfficesFitThemselvesTurnedHalfRound) {
  const std::vector<Rigid2d> moves = SymmetriesOf(testing::TwinOffices(), AllSixRooms());
  bool half_turn = false;
  for (const Rigid2d& move : moves) {
    half_turn |= ::testing::Value(move, IsNearPose(testing::TwinOfficesHalfTurn(), 0.15, 0.02));
  }
  EXPECT_TRUE(half_turn) << moves.size() << " moves found";
}

// The office alone fits itself nowhere else: its rooms differ in size and doors.
TEST(MapSymmetriesTest, TheOfficeAloneHasNone) {
  const std::vector<Rigid2d> poses = {Rigid2d(3.5, 6, 0), Rigid2d(5, 3, 0), Rigid2d(10, 6, 0),
                                      Rigid2d(10, 10, 0), Rigid2d(10, 1.5, 0), Rigid2d(16, 6, 0)};
  EXPECT_TRUE(SymmetriesOf(testing::OfficeWorld(), poses).empty());
}

}  // namespace
}  // namespace fleetmap
