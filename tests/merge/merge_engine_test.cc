#include "map_server/merge/merge_engine.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "tests/merge/merge_engine_fixtures.h"
#include "tests/merge/merge_test_worlds.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using namespace merge_fixtures;
using testing::IsNearPose;

// Two detections (no heading) from robot a of robot b, b's local frame at headings all around
// the circle: b is placed within 3 cm and 0.3 degrees.
TEST(MergeEngineTest, DetectionsAlignAnyRelativeHeading) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  for (double heading : {-3.1, -1.0, 2.2}) {
    MergeEngine engine(TestOptions());
    const SimRobot a = RobotA(), b = RobotB(heading);
    Feed(world, a, &engine);
    Feed(world, b, &engine);
    ASSERT_TRUE(engine.AddDetection(Detect(a, b, 20, false)));
    const MergeUpdate update = engine.Update();
    ASSERT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1) << "heading " << heading;
    const auto rel = EstimatedRelative(engine, "a", "b");
    ASSERT_TRUE(rel);
    EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180)) << "heading " << heading;
    EXPECT_EQ(engine.PlacedRobots().size(), 2u);
  }
}

// The trajectory and the submaps are revised separately: here b's trajectory is an older
// revision, from before a loop closure moved its map by 0.5 m, while its submaps are already
// the corrected ones. Detections are judged against the submap that hosts them, so b is still
// placed within 3 cm.
TEST(MergeEngineTest, DetectionsUseTheirHostSubmapsRevision) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MergeEngine engine(TestOptions());
  const SimRobot a = RobotA(), b = RobotB(-1.0);
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  Trajectory stale = testing::MakeTrajectory(b.path, b.local_in_world, kDt);
  for (StampedPose& p : stale) p.pose = Rigid2d(0.5, -0.2, 0.0) * p.pose;
  ASSERT_TRUE(engine.SetTrajectory("b", stale));
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, 20, false)));
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, 24, false)));
  engine.Update();
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

// The observer only mapped the left room; the seen robot comes from the middle and right rooms
// (most of its map lies beyond the observer's). Two detections without heading still align it.
TEST(MergeEngineTest, DetectionsAlignWhenTheSeenMapReachesPastTheObserver) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MergeEngine engine(TestOptions());
  SimRobot a{"a", testing::PathThrough({{1.5, 10.5}, {3, 10.5}, {3, 9}, {1.5, 9}, {1.5, 10.5}}, 0.25),
             Rigid2d(1.5, 10.5, 0.3)};
  const SimRobot b{"b", testing::PathThrough({{18, 10}, {14, 7}, {11, 5}, {10, 6}, {6, 6}, {3, 8}}, 0.25), Rigid2d(18, 10, -2.0)};
  while (a.path.size() < b.path.size()) a.path.push_back(a.path.back());  // a waits
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  const size_t last = b.path.size() - 1;
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, last - 4, false)));
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, last, false)));
  const MergeUpdate update = engine.Update();
  for (const AlignmentEvent& e : update.events) {
    if (e.evidence != EvidenceKind::kDetection) continue;  // joined, a's submaps match b's map
    EXPECT_LT(e.overlap, 0.7) << AlignmentEventTypeName(e.type) << " " << e.reason;
  }
  ASSERT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

// Robots in a long featureless corridor: submap matching alone must not merge them.
TEST(MergeEngineTest, CorridorDoesNotMergeWithoutDetection) {
  const testing::SegmentWorld world = testing::CorridorWorld();
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  MergeEngine engine(options);
  const SimRobot a{"a", testing::PathThrough({{3, 1}, {15, 1}}, 0.25), Rigid2d(3, 1, 0.0)};
  const SimRobot b{"b", testing::PathThrough({{20, 1}, {8, 1}}, 0.25), Rigid2d(20, 1, 1.0)};
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  for (int i = 0; i < 3; ++i) {
    const MergeUpdate update = engine.Update();
    EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  }
  EXPECT_FALSE(engine.RobotToGlobal("b"));
  EXPECT_TRUE(engine.RobotToGlobal("a"));
}

// In a corridor, the seen robot's map turned end for end about the detected position fits the
// observer's map as well, and better where more of it lands on the observer's map. Detections of
// a robot standing still say nothing about its heading, and neither does matching more of its
// own map: they must not confirm each other into an alignment.
TEST(MergeEngineTest, DetectionsOfAStandingRobotInACorridorDoNotMerge) {
  const testing::SegmentWorld world = testing::CorridorWorld();
  MergeEngine engine(TestOptions());
  SimRobot a{"a", testing::PathThrough({{2, 1}, {10, 1}}, 0.25), Rigid2d(2, 1, 0.0)};
  SimRobot b{"b", testing::PathThrough({{28, 1}, {16, 1}}, 0.25), Rigid2d(28, 1, 0.7)};
  const size_t stop = b.path.size();
  while (b.path.size() < stop + 15) b.path.push_back(b.path.back());  // b stands still
  while (a.path.size() < b.path.size()) a.path.push_back(a.path.back());
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  for (size_t step : {stop + 1, stop + 7, stop + 14}) ASSERT_TRUE(engine.AddDetection(Detect(a, b, step, false)));
  const MergeUpdate update = engine.Update();
  for (const AlignmentEvent& e : update.events) {
    EXPECT_NE(e.type, AlignmentEventType::kAlignmentAccepted) << e.reason;
  }
  EXPECT_FALSE(engine.RobotToGlobal("b"));
}

// The same corridor with the seen robot driving: its map turned end for end still fits better
// (more of it lands on the observer's map), but where it moved, seen from the observer, against
// where it moved in its own map gives the heading; searched around that, the detections align it.
TEST(MergeEngineTest, DetectionsOfADrivingRobotInACorridorAlignItByItsMotion) {
  MergeEngine engine(TestOptions());
  const auto [a, b] = FeedCorridorApproach(&engine);
  const size_t last = b.path.size() - 1;
  for (size_t step : {last - 12, last - 8, last - 4, last}) {
    ASSERT_TRUE(engine.AddDetection(Detect(a, b, step, false)));
  }
  const MergeUpdate update = engine.Update();
  EXPECT_GE(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  // The heading is right (turned end for end, b would be metres off). Along a featureless
  // corridor only the detections fix the position, but the match edge claims 2 cm there too
  // (isotropic match sigmas), so the lattice's pick within the detection window stays.
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.25, 0.5 * M_PI / 180));
}

// 20 detections, two of them corrupted (10 %): the corrupted ones are rejected, never used.
TEST(MergeEngineTest, CorruptedDetectionsAreRejected) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MergeEngine engine(TestOptions());
  const SimRobot a = RobotA(), b = RobotB(0.8);
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  std::set<size_t> corrupted;
  std::mt19937 rng(7);
  for (size_t k = 0; k < 20; ++k) {
    const size_t step = 10 + 2 * k;
    RobotDetection d = Detect(a, b, step, k % 3 == 0);
    if (k == 0 || k == 12) {  // one before and one after the alignment is found
      d.position_in_observer += Eigen::Vector2d(1.5, -1.0);
      corrupted.insert(k);
    }
    ASSERT_TRUE(engine.AddDetection(d));
  }
  const MergeUpdate update = engine.Update();
  for (const AlignmentEvent& e : update.events) {
    if (!e.detection_index || !corrupted.count(*e.detection_index)) continue;
    EXPECT_TRUE(e.type == AlignmentEventType::kRejected || e.type == AlignmentEventType::kHypothesis)
        << "corrupted detection " << *e.detection_index << ": " << AlignmentEventTypeName(e.type) << " " << e.reason;
  }
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
  EXPECT_LT(engine.Quality().inter_robot_rms_translation, 0.05);
}

// No detections at all but large overlap: cross-robot matching merges, correctly.
TEST(MergeEngineTest, CrossMatchingMergesWithoutDetections) {
  const SimRobot a = RobotA(), b = RobotB(-2.4);
  auto engine_owner = OverlappingRobotsWithSearches(a, b);
  MergeEngine& engine = *engine_owner;
  const MergeUpdate update = engine.Update();
  EXPECT_GE(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

// The same two submaps matched each way round (a's against b's map, b's against a's) are one
// piece of evidence seen twice: where one slides along a corridor, the other slides with it (on
// the merge bench's east_end scenario without detections, robot3 was first joined 3.3 m along
// its corridor that way). With one submap each, nothing else can confirm the match.
TEST(MergeEngineTest, ASubmapMatchAndItsReverseDoNotConfirmEachOther) {
  SimRobot a{"a", testing::PathThrough({{5, 6}, {9, 6}}, 0.25), Rigid2d(5, 6, 0.3)};
  SimRobot b{"b", testing::PathThrough({{9, 6.3}, {5, 6.3}}, 0.25), Rigid2d(9, 6.3, -2.4)};
  a.path.resize(10);  // one submap each
  b.path.resize(10);
  auto engine_owner = OverlappingRobotsWithSearches(a, b);
  MergeEngine& engine = *engine_owner;
  int hypotheses = 0;
  for (int i = 0; i < 3; ++i) {
    const MergeUpdate update = engine.Update();
    hypotheses += Count(update, AlignmentEventType::kHypothesis);
    EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  }
  EXPECT_GE(hypotheses, 2);  // both matches were found, each kept waiting for other evidence
  EXPECT_FALSE(EstimatedRelative(engine, "a", "b"));
}

// A single detection that no other submap can confirm stays a hypothesis; a second, independent
// detection that agrees turns it into an alignment.
TEST(MergeEngineTest, SingleDetectionStaysHypothesisUntilConfirmed) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  MergeEngine engine(TestOptions());
  SimRobot a = RobotA(), b = RobotB(1.7);
  b.path.resize(10);  // one submap only: nothing else of b to verify with
  Feed(world, a, &engine);
  Feed(world, b, &engine);
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, 2, false)));
  MergeUpdate update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kHypothesis), 1);
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  EXPECT_FALSE(engine.RobotToGlobal("b"));
  ASSERT_TRUE(engine.AddDetection(Detect(a, b, 8, true)));
  update = engine.Update();
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 1);
  const auto rel = EstimatedRelative(engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_THAT(*rel, IsNearPose(TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

// Local SLAM drift (anchors rotate and slide a little more with every submap) around a loop:
// the loop closure against the robot's own first submaps pulls the end back towards the truth.
TEST(MergeEngineTest, LoopClosureCorrectsDrift) {
  const testing::SegmentWorld world = testing::OfficeWorld();
  const std::vector<Rigid2d> path =
      testing::PathThrough({{8, 1.2}, {12, 1.2}, {12, 7}, {8, 7.2}, {8, 1.2}, {11, 1.2}}, 0.25);
  std::vector<Submap> submaps = testing::MakeSubmaps("a", world, path, Rigid2d(), 5);
  std::vector<Rigid2d> truth;
  for (Submap& s : submaps) {
    truth.push_back(s.submap_in_local);
    const double k = static_cast<double>(s.submap_id);
    s.submap_in_local = Rigid2d(0.005 * k, 0.0, 0.001 * k) * s.submap_in_local;
  }
  const Rigid2d true_rel = truth.front().inverse() * truth.back();
  const Rigid2d drifted_rel = submaps.front().submap_in_local.inverse() * submaps.back().submap_in_local;
  const double drift = (true_rel.inverse() * drifted_rel).translation().norm();
  ASSERT_GT(drift, 0.1);
  MergeEngineOptions options = TestOptions();
  options.max_loop_searches_per_update = 100;
  MergeEngine engine(options);
  for (const Submap& s : submaps) ASSERT_TRUE(engine.AddOrUpdateSubmap(s));
  const MergeUpdate update = engine.Update();
  int closures = 0;
  for (const AlignmentEvent& e : update.events) closures += e.evidence == EvidenceKind::kLoopClosure;
  EXPECT_GE(closures, 1);
  const auto poses = engine.SubmapPoses();
  const Rigid2d rel = poses.at({"a", 0}).inverse() * poses.at({"a", submaps.back().submap_id});
  EXPECT_LT((true_rel.inverse() * rel).translation().norm(), 0.3 * drift);
  // The robot's start stays where its first submap holds the global frame; the frame its newest
  // submap implies moved with the correction (0.087 m here).
  const auto start = engine.RobotStartToGlobal("a"), newest = engine.RobotToGlobal("a");
  ASSERT_TRUE(start && newest);
  EXPECT_THAT(*start, IsNearPose(Rigid2d(), 1e-9, 1e-9));
  EXPECT_THAT(*newest, IsNearPose(poses.at({"a", submaps.back().submap_id}) *
                                      submaps.back().submap_in_local.inverse(),
                                  1e-9, 1e-9));
  const double moved = (start->inverse() * *newest).translation().norm();
  std::printf("drift %.3f m, newest submap's frame %.3f m from the start's\n", drift, moved);
  EXPECT_GT(moved, 0.25 * drift);
}

// A robot with nothing linking it to the others stays unplaced.
TEST(MergeEngineTest, UnconnectedRobotStaysUnplaced) {
  MergeEngine engine(TestOptions());
  Feed(testing::OfficeWorld(), RobotA(), &engine);
  Feed(testing::OfficeWorld(), RobotB(1.0), &engine);
  engine.Update();
  EXPECT_TRUE(engine.RobotToGlobal("a"));
  EXPECT_THAT(*engine.RobotToGlobal("a"), IsNearPose(Rigid2d(), 1e-9, 1e-9));
  EXPECT_FALSE(engine.RobotToGlobal("b"));
  EXPECT_EQ(engine.PlacedRobots(), std::vector<std::string>{"a"});
}

// Robots registered with known starts are placed there at once and define the global frame.
TEST(MergeEngineTest, KnownPlacementsArePlacedDirectly) {
  MergeEngine engine(TestOptions());
  const SimRobot a = RobotA(), b = RobotB(0.4);
  ASSERT_TRUE(engine.SetKnownPlacement("b", b.local_in_world));
  ASSERT_TRUE(engine.SetKnownPlacement("a", a.local_in_world));
  Feed(testing::OfficeWorld(), a, &engine);
  Feed(testing::OfficeWorld(), b, &engine);
  engine.Update();
  ASSERT_TRUE(engine.RobotToGlobal("a") && engine.RobotToGlobal("b"));
  EXPECT_THAT(*engine.RobotToGlobal("a"), IsNearPose(a.local_in_world, 0.01, 0.002));
  EXPECT_THAT(*engine.RobotToGlobal("b"), IsNearPose(b.local_in_world, 0.01, 0.002));
  EXPECT_EQ(engine.reference_robot(), "b");
  std::string error;
  EXPECT_FALSE(engine.SetKnownPlacement("a", Rigid2d(), &error));  // already in the map
}

TEST(MergeEngineTest, RejectsInvalidInput) {
  MergeEngine engine;
  std::string error;
  RobotDetection d;
  d.observer_id = "a";
  d.observed_id = "a";
  EXPECT_FALSE(engine.AddDetection(d, &error));
  d.observed_id = "b";
  d.covariance << 1, 0, 0, -1;
  EXPECT_FALSE(engine.AddDetection(d, &error));
  EXPECT_FALSE(error.empty());
  Submap s;
  s.robot_id = "a";
  s.revision = 2;
  EXPECT_TRUE(engine.AddOrUpdateSubmap(s, &error));
  s.revision = 1;
  EXPECT_FALSE(engine.AddOrUpdateSubmap(s, &error));
  s.robot_id = "";
  EXPECT_FALSE(engine.AddOrUpdateSubmap(s, &error));
  EXPECT_FALSE(engine.SetTrajectory("a", {{1.0, Rigid2d()}, {0.5, Rigid2d()}}, &error));
  EXPECT_FALSE(engine.RenderGlobalMap(std::nullopt, -1.0, &error));
  EXPECT_FALSE(engine.RenderGlobalMap(Box2d{{0, 0}, {1e6, 1e6}}, 0.01, &error));
}

}  // namespace
}  // namespace fleetmap
