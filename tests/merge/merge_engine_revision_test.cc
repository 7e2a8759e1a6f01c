// Evidence that arrives later revises the merge: detections already received veto a match,
// detections that keep contradicting a join withdraw it, and detections whose search failed are
// tried again when the submaps of their time arrive.

#include "map_server/merge/merge_engine.h"

#include <gtest/gtest.h>

#include "tests/merge/merge_engine_fixtures.h"
#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using namespace merge_fixtures;
using testing::IsNearPose;

// A detection of b by a at `step`, reported 3 m off (consistent with others like it, wrong).
RobotDetection MisplacedDetection(const SimRobot& a, const SimRobot& b, size_t step) {
  RobotDetection d = Detect(a, b, step, false);
  d.position_in_observer += Eigen::Vector2d(3.0, 0.0);
  return d;
}

// Detections already received overrule a submap match that contradicts them: in a nearly
// symmetric building the map turned round matches as well as the true one, and every further
// submap agrees with it. Here the detections (consistent with each other) put b 3 m from where
// the match would; the match must not be accepted, and the event says why.
TEST(MergeEngineTest, DetectionsThatContradictAMatchOverruleIt) {
  const SimRobot a = RobotA(), b = RobotB(-2.4);
  auto engine_owner = OverlappingRobotsWithSearches(a, b);
  MergeEngine& engine = *engine_owner;
  for (size_t step : {10u, 20u, 30u}) ASSERT_TRUE(engine.AddDetection(MisplacedDetection(a, b, step)));
  const MergeUpdate update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  bool overruled = false;
  for (const AlignmentEvent& e : update.events) {
    overruled = overruled || (e.evidence == EvidenceKind::kCrossMatch &&
                              e.reason.find("contradicted by 3 detections") != std::string::npos);
  }
  EXPECT_TRUE(overruled);
  EXPECT_FALSE(EstimatedRelative(engine, "a", "b").has_value());
}

// A join that later detections contradict is withdrawn, and those detections place the robot
// again. Three consistent but wrong detections (b reported 1.5 m nearer along a featureless
// corridor, e.g. a mis-ranged marker) join b there, as matching can join a robot turned round
// before any detection of it arrives. Five correct ones follow: each alone is an outlier of the
// joined map, together they outvote the three, b is split off, and judged again they align it.
TEST(MergeEngineTest, AJoinThatLaterDetectionsContradictIsWithdrawnAndRedone) {
  MergeEngine engine(TestOptions());
  const auto [a, b] = FeedCorridorApproach(&engine);
  const size_t last = b.path.size() - 1;
  for (size_t step : {last - 22, last - 18, last - 14}) {
    RobotDetection d = Detect(a, b, step, false);
    d.position_in_observer -= Eigen::Vector2d(1.5, 0.0);
    ASSERT_TRUE(engine.AddDetection(d));
  }
  MergeUpdate update = engine.Update();
  ASSERT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  ASSERT_GT((TrueRelative(a, b).inverse() * *rel).translation().norm(), 1.0);  // the wrong join

  for (size_t step : {last - 8, last - 6, last - 4, last - 2, last}) ASSERT_TRUE(engine.AddDetection(Detect(a, b, step, false)));
  update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kWithdrawn), 1);
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.25, 0.5 * M_PI / 180));
  // The three wrong detections are outliers of the new alignment, and stay so.
  update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kWithdrawn), 0);
}

// Detections that contradict a join but agree with no other alignment either (b reported 3 m
// off in a room-structured office) unplace b, and it stays unplaced: a wrong map is worse than
// a missing robot. The reference robot keeps the global frame.
TEST(MergeEngineTest, AJoinContradictedByDetectionsLeavesTheRobotUnplaced) {
  const SimRobot a = RobotA(), b = RobotB(-2.4);
  auto engine_owner = OverlappingRobotsWithSearches(a, b);
  MergeEngine& engine = *engine_owner;
  engine.Update();
  ASSERT_TRUE(EstimatedRelative(engine, "a", "b"));
  const Rigid2d a_before = *engine.RobotToGlobal("a");
  for (size_t step : {10u, 20u, 30u, 40u}) ASSERT_TRUE(engine.AddDetection(MisplacedDetection(a, b, step)));
  MergeUpdate update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kWithdrawn), 1);
  EXPECT_TRUE(update.changed_region.has_value());
  while (engine.HasPendingWork()) engine.Update();
  EXPECT_FALSE(engine.RobotToGlobal("b"));
  ASSERT_TRUE(engine.RobotToGlobal("a"));
  EXPECT_THAT(*engine.RobotToGlobal("a"), IsNearPose(a_before, 0.02, 0.002));  // a relaxes a little without b
  EXPECT_EQ(engine.PlacedRobots(), std::vector<std::string>{"a"});
}

// A join is withdrawn only on a clear majority: a robot that drifts, or a stream with outliers,
// gives both agreeing and contradicting detections in numbers. With 4 agreeing, 5 contradicting
// ones keep b joined; 7 (more than 1.5 times as many) withdraw it.
TEST(MergeEngineTest, AJoinIsWithdrawnOnlyWhenAClearMajorityContradictsIt) {
  const SimRobot a = RobotA(), b = RobotB(-2.4);
  auto engine_owner = OverlappingRobotsWithSearches(a, b);
  MergeEngine& engine = *engine_owner;
  engine.Update();
  ASSERT_TRUE(EstimatedRelative(engine, "a", "b"));
  for (size_t step : {5u, 15u, 25u, 35u}) ASSERT_TRUE(engine.AddDetection(Detect(a, b, step, false)));
  for (size_t step : {10u, 20u, 30u, 40u, 45u}) ASSERT_TRUE(engine.AddDetection(MisplacedDetection(a, b, step)));
  MergeUpdate update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kWithdrawn), 0);
  EXPECT_THAT(*EstimatedRelative(engine, "a", "b"), IsNearPose(TrueRelative(a, b), 0.1, 0.01));

  for (size_t step : {12u, 22u}) ASSERT_TRUE(engine.AddDetection(MisplacedDetection(a, b, step)));
  update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kWithdrawn), 1);
}

// At full speed detections often reach the server before the submaps that show the meeting:
// here b's submaps first arrive as empty snapshots, so the heading search has nothing to match
// and fails. When b's finished submaps near the detections' time arrive, the detections are
// judged again and align b.
TEST(MergeEngineTest, DetectionsAreTriedAgainWhenTheSubmapsOfTheirTimeArrive) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MergeEngine engine(TestOptions());
  const SimRobot a = RobotA(), b = RobotB(1.7);
  Feed(world, a, &engine);
  const std::vector<Submap> finished = testing::MakeSubmaps(b.id, world, b.path, b.local_in_world, 10, kDt);
  for (Submap snapshot : finished) {
    snapshot.grid = OccupancyGrid(snapshot.grid.options());
    snapshot.finished = false;
    ASSERT_TRUE(engine.AddOrUpdateSubmap(snapshot));
  }
  ASSERT_TRUE(engine.SetTrajectory(b.id, testing::MakeTrajectory(b.path, b.local_in_world, kDt)));
  for (size_t step : {10u, 16u, 22u}) ASSERT_TRUE(engine.AddDetection(Detect(a, b, step, false)));
  MergeUpdate update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  EXPECT_GE(Count(update, AlignmentEventType::kRejected), 3);
  EXPECT_FALSE(engine.RobotToGlobal("b"));
  for (Submap s : finished) {
    s.revision = 1;
    ASSERT_TRUE(engine.AddOrUpdateSubmap(s));
  }
  update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

}  // namespace
}  // namespace fleetmap
