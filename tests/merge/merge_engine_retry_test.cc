// A submap searched over another robot's map before that map reached its walls is searched
// again once that map has grown (MergeEngineOptions::cross_retry_growth): a restarted server
// searches every stored submap over the maps of that moment.

#include <gtest/gtest.h>

#include <vector>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"
#include "tests/merge/merge_test_worlds.h"

namespace fleetmap {
namespace {

using namespace merge_fixtures;

// Whether any event came from a global search of `robot`'s submap `id` (a local constraint, the
// match of a submap already joined, is not one).
bool Searched(const std::vector<MergeUpdate>& updates, const std::string& robot, int64_t id) {
  for (const MergeUpdate& u : updates) {
    for (const AlignmentEvent& e : u.events) {
      if (e.evidence == EvidenceKind::kCrossMatch &&
          e.type != AlignmentEventType::kConstraintAdded && e.robot_b == robot &&
          e.submaps_b == std::vector<int64_t>{id})
        return true;
    }
  }
  return false;
}

// Robot "a" keeps to the office's right room; robot "b" has sent only its first submap (the left
// room, which a never saw) when a's map arrives, then the rest of its tour through the middle
// room into the right one. Returns the events of the updates after b's map has grown.
std::vector<MergeUpdate> GrowAfterSearch(double cross_retry_growth) {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  options.cross_retry_growth = cross_retry_growth;
  MergeEngine engine(options);
  const testing::SegmentWorld world = testing::OfficeWorld();
  const SimRobot a{"a", testing::PathThrough({{16.5, 5}, {18.5, 5}, {18.5, 7}, {16.5, 6.5}}, 0.25),
                   Rigid2d(16.5, 5, -2.4)};
  const SimRobot b{
      "b", testing::PathThrough({{2, 6}, {6, 6}, {10, 5}, {14.5, 5}, {18, 5}, {18, 7}}, 0.25),
      Rigid2d(2, 6, 0.3)};
  Feed(world, a, &engine);
  std::string error;
  const std::vector<Submap> b_submaps =
      testing::MakeSubmaps(b.id, world, b.path, b.local_in_world, 10, kDt);
  EXPECT_GE(b_submaps.size(), 4u);
  EXPECT_TRUE(engine.AddOrUpdateSubmap(b_submaps.front(), &error)) << error;
  EXPECT_TRUE(engine.SetTrajectory(b.id, testing::MakeTrajectory(b.path, b.local_in_world, kDt)));
  // Update() makes the graph's nodes; until then nothing is pending.
  for (int i = 0; i == 0 || (i < 10 && engine.HasPendingWork()); ++i) engine.Update();
  std::vector<MergeUpdate> after;
  for (size_t i = 1; i < b_submaps.size(); ++i)
    EXPECT_TRUE(engine.AddOrUpdateSubmap(b_submaps[i], &error)) << error;
  for (int i = 0; i == 0 || (i < 10 && engine.HasPendingWork()); ++i)
    after.push_back(engine.Update());
  return after;
}

// a's first submap shows the right room, which b's first submap did not reach: searched again
// over b's grown map, it is what joins them.
TEST(MergeEngineRetryTest, ASubmapIsSearchedAgainOnceTheOtherMapHasGrown) {
  EXPECT_TRUE(Searched(GrowAfterSearch(2.0), "a", 0));
}

// The same without retries: the first search was the only one (so the test above can fail).
TEST(MergeEngineRetryTest, WithoutRetriesASubmapIsSearchedOnce) {
  EXPECT_FALSE(Searched(GrowAfterSearch(0.0), "a", 0));
}

}  // namespace
}  // namespace fleetmap
