// A join on matches alone must not be accepted while the two whole maps fit as well turned round
// (MergeEngineOptions::whole_map_ambiguity), unless the maps' own walls rule the other fit out
// (MergeEngineOptions::whole_map_min_contradictions).

#include <gtest/gtest.h>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"

namespace fleetmap {
namespace {

using merge_fixtures::Count;
using merge_fixtures::EstimatedRelative;
using merge_fixtures::Feed;
using merge_fixtures::SimRobot;
using merge_fixtures::TrueRelative;
using testing::TwinOffices;
using testing::TwinOfficesHalfTurn;

std::vector<Rigid2d> Turned(const std::vector<Rigid2d>& path) {
  std::vector<Rigid2d> out;
  for (const Rigid2d& p : path) out.push_back(TwinOfficesHalfTurn() * p);
  return out;
}

// The office's three rooms, left to right and round the right room, then `tail`: 0.25 m steps.
std::vector<Rigid2d> OfficeTour(std::vector<Eigen::Vector2d> tail) {
  std::vector<Eigen::Vector2d> waypoints = {{2, 6},    {5.5, 5.5}, {8, 6},  {11, 5},   {14, 5},
                                            {18.5, 5}, {18.5, 9},  {14, 9}, {18.5, 9}, {18.5, 5}};
  waypoints.insert(waypoints.end(), tail.begin(), tail.end());
  return testing::PathThrough(waypoints, 0.25);
}

// Robot a drives the turned office's three rooms, then the office's right and middle rooms
// (never its left room). Robot b starts in the office's left room and drives on into the middle
// and right rooms, where it stays. b's first submaps show a room a saw only turned round: each
// matches there unambiguously, and two of them agree on the turned alignment. Over b's whole
// map the true alignment fits nearly as well (a saw the rooms b spends most of its time in both
// ways round), so the join must wait.
std::pair<SimRobot, SimRobot> TwinOfficeRobots() {
  const std::vector<Rigid2d> tour = OfficeTour({{11, 6}});
  std::vector<Rigid2d> a_path = Turned(tour);
  for (const Rigid2d& p : testing::PathThrough(
           {{21.5, 6}, {18.5, 6}, {18.5, 9}, {14.5, 9}, {18.5, 9}, {18.5, 5}, {14, 5}, {11, 6}}, 0.25)) {
    a_path.push_back(p);
  }
  SimRobot a{"a", a_path, Rigid2d(a_path.front().translation(), 0.4)};
  const std::vector<Rigid2d> b_path = testing::PathThrough(
      {{1.5, 5.5}, {5.5, 5.5}, {8, 6}, {11.5, 5}, {14, 5}, {18.5, 5}, {18.5, 9}, {14.5, 9},
       {18.5, 9}, {18.5, 5}, {14, 5}, {11.5, 6.5}, {8.5, 4}},
      0.25);
  SimRobot b{"b", b_path, Rigid2d(b_path.front().translation(), -1.1)};
  return {a, b};
}

// As above, but b keeps to the office's middle and right rooms, which a saw both ways round:
// the true and the turned fits explain b's map as fully, apart from the crates.
std::pair<SimRobot, SimRobot> CrateRobots() {
  SimRobot a = TwinOfficeRobots().first;
  const std::vector<Rigid2d> b_path = testing::PathThrough({{8, 6},
                                                            {11.5, 5},
                                                            {14, 5},
                                                            {18.5, 5},
                                                            {18.5, 9},
                                                            {14.5, 9},
                                                            {18.5, 9},
                                                            {18.5, 5},
                                                            {14, 5},
                                                            {11.5, 6.5},
                                                            {8.5, 4}},
                                                           0.25);
  SimRobot b{"b", b_path, Rigid2d(b_path.front().translation(), -1.1)};
  return {a, b};
}

std::unique_ptr<MergeEngine> FedEngine(
    double whole_map_ambiguity, SimRobot* a, SimRobot* b, bool crates = false,
    int min_contradictions = MergeEngineOptions().whole_map_min_contradictions) {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  options.whole_map_ambiguity = whole_map_ambiguity;
  options.whole_map_min_contradictions = min_contradictions;
  auto engine = std::make_unique<MergeEngine>(options);
  const testing::SegmentWorld world = TwinOffices(crates);
  std::tie(*a, *b) = crates ? CrateRobots() : TwinOfficeRobots();
  Feed(world, *a, engine.get());
  Feed(world, *b, engine.get());
  return engine;
}

TEST(MergeEngineAmbiguityTest, WithoutTheWholeMapCheckTwoSubmapsJoinTheTwinTurnedRound) {
  SimRobot a, b;
  auto engine = FedEngine(0.0, &a, &b);
  engine->Update();
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel) << "the case the next test is about: a join on the turned twin";
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_GT(error.translation().norm(), 5.0);
}

TEST(MergeEngineAmbiguityTest, AJoinWaitsWhileTheWholeMapsFitTurnedRound) {
  SimRobot a, b;
  auto engine = FedEngine(MergeEngineOptions().whole_map_ambiguity, &a, &b);
  // One update searches every submap (the budget is large).
  const MergeUpdate update = engine->Update();
  int kept = 0;
  for (const AlignmentEvent& e : update.events) {
    kept += e.type == AlignmentEventType::kHypothesis &&
            e.reason.find("ambiguous over the whole maps") != std::string::npos;
  }
  EXPECT_EQ(Count(update, AlignmentEventType::kAlignmentAccepted), 0);
  EXPECT_GE(kept, 1);
  EXPECT_FALSE(engine->RobotToGlobal("b"));
}

// The check does not stop a join where nothing else fits: the office alone.
TEST(MergeEngineAmbiguityTest, AnUnambiguousJoinIsStillAccepted) {
  const SimRobot a = merge_fixtures::RobotA(), b = merge_fixtures::RobotB(-2.4);
  auto engine = merge_fixtures::OverlappingRobotsWithSearches(a, b);
  engine->Update();
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel);
  EXPECT_LT((TrueRelative(a, b).inverse() * *rel).translation().norm(), 0.05);
}

// The crates tell the twins apart: the turned fit puts b's crates inside rooms a saw empty, and
// a's crates inside space b saw free. Their walls are too few for the score to tell.
TEST(MergeEngineAmbiguityTest, WallsSeenThroughRuleOutTheTurnedFit) {
  SimRobot a, b;
  auto engine = FedEngine(MergeEngineOptions().whole_map_ambiguity, &a, &b, /*crates=*/true);
  MergeUpdate update;
  for (int i = 0; i < 5 && !engine->RobotToGlobal("b"); ++i) update = engine->Update();
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel);
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_LT(error.translation().norm(), 0.05);
  EXPECT_LT(std::abs(error.rotation()), 0.01);
  bool noted = false;
  for (const AlignmentEvent& e : update.events) {
    noted |= e.type == AlignmentEventType::kAlignmentAccepted &&
             e.reason.find("walls rule out") != std::string::npos;
  }
  EXPECT_TRUE(noted) << "the provenance says which alignments the walls ruled out";
}

TEST(MergeEngineAmbiguityTest, WithoutCountingWallsSeenThroughTheCratesAreNotEnough) {
  SimRobot a, b;
  auto engine = FedEngine(MergeEngineOptions().whole_map_ambiguity, &a, &b, /*crates=*/true,
                          /*min_contradictions=*/0);
  for (int i = 0; i < 5; ++i) engine->Update();
  EXPECT_FALSE(engine->RobotToGlobal("b"));
}

// Robot a drives the turned office only, robot b the office only: their maps do not overlap,
// and b's fits a's turned round, the only alignment that scores. But the office has two walls
// its twin lacks (in its left and middle rooms), and at that alignment they stand where a saw
// through: the join must not be made.
std::unique_ptr<MergeEngine> UnlikeTwinsEngine(int min_contradictions, SimRobot* a, SimRobot* b) {
  testing::SegmentWorld world = TwinOffices();
  world.push_back({Eigen::Vector2d(0, 8.5), Eigen::Vector2d(4, 8.5)});
  world.push_back({Eigen::Vector2d(8, 10), Eigen::Vector2d(12, 10)});
  const std::vector<Rigid2d> tour = OfficeTour({{11, 6}, {8, 6}, {3, 6}});
  const std::vector<Rigid2d> a_path = Turned(tour);
  *a = SimRobot{"a", a_path, Rigid2d(a_path.front().translation(), 0.4)};
  *b = SimRobot{"b", tour, Rigid2d(tour.front().translation(), -1.1)};
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  options.whole_map_min_contradictions = min_contradictions;
  auto engine = std::make_unique<MergeEngine>(options);
  Feed(world, *a, engine.get());
  Feed(world, *b, engine.get());
  return engine;
}

TEST(MergeEngineAmbiguityTest, AJoinWhoseWallsStandWhereTheOtherSawThroughIsNotMade) {
  SimRobot a, b;
  auto engine = UnlikeTwinsEngine(MergeEngineOptions().whole_map_min_contradictions, &a, &b);
  bool refused = false;
  for (int i = 0; i < 5; ++i) {
    for (const AlignmentEvent& e : engine->Update().events) {
      refused |= e.reason.find("the whole maps contradict it") != std::string::npos;
      if (e.type == AlignmentEventType::kAlignmentAccepted) ADD_FAILURE() << e.reason;
    }
  }
  EXPECT_FALSE(engine->RobotToGlobal("b"));
  EXPECT_TRUE(refused) << "the provenance says why the join waits";
}

TEST(MergeEngineAmbiguityTest, WithoutCountingWallsSeenThroughTheUnlikeTwinsJoin) {
  SimRobot a, b;
  auto engine = UnlikeTwinsEngine(/*min_contradictions=*/0, &a, &b);
  for (int i = 0; i < 5; ++i) engine->Update();
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel) << "the case the test above is about: a join on the turned twin";
  EXPECT_GT((TrueRelative(a, b).inverse() * *rel).translation().norm(), 5.0);
}

// Robot a drives the turned office's three rooms, then the office's right room and into its
// middle room up to x = `reach`; robot b the office's left and middle rooms. b's map fits a's
// turned round all over (a saw those rooms turned round), and at the true alignment it overlaps
// a's map only where a looked into the middle room: it scores too little over b's whole map for
// the search by score to reach it, yet nothing in the maps tells the two apart. a's map fits
// itself turned half round (its right rooms), and the turned join moved by that turn is the true
// alignment: the join must wait.
std::unique_ptr<MergeEngine> TwinOfTheJoinEngine(MergeEngineOptions options, SimRobot* a,
                                                 SimRobot* b, double reach = 14.5) {
  const std::vector<Rigid2d> tour = OfficeTour({{19, 6}});
  std::vector<Rigid2d> a_path = Turned(tour);
  for (const Rigid2d& p : testing::PathThrough(
           {{21.5, 6}, {18.5, 6}, {18.5, 9}, {14.5, 9}, {18.5, 9}, {18.5, 5}, {reach, 5}}, 0.25)) {
    a_path.push_back(p);
  }
  *a = SimRobot{"a", a_path, Rigid2d(a_path.front().translation(), 0.4)};
  const std::vector<Rigid2d> b_path = testing::PathThrough(
      {{1.5, 5.5}, {3.5, 6}, {5.5, 5.5}, {8, 6}, {10, 6}, {11.5, 9.5}, {11.5, 6}, {8.5, 4}}, 0.25);
  *b = SimRobot{"b", b_path, Rigid2d(b_path.front().translation(), -1.1)};
  options.max_global_searches_per_update = 100;
  auto engine = std::make_unique<MergeEngine>(options);
  Feed(TwinOffices(), *a, engine.get());
  Feed(TwinOffices(), *b, engine.get());
  return engine;
}

// The search for alternatives by score alone, without the maps' symmetries.
MergeEngineOptions SearchByScore() {
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.whole_map_symmetry_max_examined = 0;
  options.whole_map_unseen_score = 0.0;
  return options;
}

void ExpectTheJoinOnTheTwin(MergeEngine* engine, const SimRobot& a, const SimRobot& b) {
  for (int i = 0; i < 5; ++i) engine->Update();
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel) << "the case the next tests are about: a join on the turned twin";
  EXPECT_GT((TrueRelative(a, b).inverse() * *rel).translation().norm(), 5.0);
}

// The join waits, and its provenance says why (`why`).
void ExpectTheJoinToWait(MergeEngine* engine, const std::string& why) {
  bool noted = false;
  for (int i = 0; i < 5; ++i) {
    for (const AlignmentEvent& e : engine->Update().events) {
      noted |= e.reason.find(why) != std::string::npos;
      if (e.type == AlignmentEventType::kAlignmentAccepted) ADD_FAILURE() << e.reason;
    }
  }
  EXPECT_FALSE(engine->RobotToGlobal("b"));
  EXPECT_TRUE(noted) << "the provenance says why the join waits";
}

TEST(MergeEngineAmbiguityTest, WithoutTheMapsSymmetriesTheJoinOnTheTwinIsMade) {
  SimRobot a, b;
  auto engine = TwinOfTheJoinEngine(SearchByScore(), &a, &b);
  ExpectTheJoinOnTheTwin(engine.get(), a, b);
}

TEST(MergeEngineAmbiguityTest, AJoinWaitsOnItsTwinUnderTheMapsOwnSymmetry) {
  SimRobot a, b;
  MergeEngineOptions options = SearchByScore();
  options.whole_map_symmetry_max_examined = 32;
  auto engine = TwinOfTheJoinEngine(options, &a, &b);
  ExpectTheJoinToWait(engine.get(), "moved by a symmetry of one map");
}

// With a's map reaching further into the middle room, the true alignment lands about half as
// much of b's map on a's as the join, as consistently. Ordered by score over all of b's points,
// the search still does not reach it in time.
TEST(MergeEngineAmbiguityTest, OrderedByScoreTheAlternativesMissAnAlignmentOverlappingLess) {
  SimRobot a, b;
  MergeEngineOptions options = SearchByScore();
  auto engine = TwinOfTheJoinEngine(options, &a, &b, /*reach=*/12.0);
  ExpectTheJoinOnTheTwin(engine.get(), a, b);
}

// Scored with unseen space neutral, the search reaches it first, and the join waits.
TEST(MergeEngineAmbiguityTest, AJoinWaitsOnAnAlignmentAsConsistentWhereTheMapsOverlap) {
  SimRobot a, b;
  MergeEngineOptions options = SearchByScore();
  options.whole_map_unseen_score = 0.5;
  auto engine = TwinOfTheJoinEngine(options, &a, &b, /*reach=*/12.0);
  ExpectTheJoinToWait(engine.get(), "ambiguous over the whole maps");
}

// Robot a passed robot b where b drove in the office: a's map holds b's body at places on b's
// path that b's own scans saw free once it had moved on. At the true join those "walls" stand in
// space b saw through; they are b's body, not a reason to doubt the join.
std::unique_ptr<MergeEngine> BodiesEngine(double body_radius, SimRobot* a, SimRobot* b) {
  *a = merge_fixtures::RobotA();
  *b = merge_fixtures::RobotB(-2.4);
  testing::SegmentWorld seen_by_a = testing::OfficeWorld();
  for (const Eigen::Vector2d& body :
       {Eigen::Vector2d(3.5, 4.9), Eigen::Vector2d(4.1, 5.31), Eigen::Vector2d(3.5, 7.1),
        Eigen::Vector2d(3.5, 7.7), Eigen::Vector2d(10.55, 8.2)}) {
    testing::AddBox(body - Eigen::Vector2d(0.2, 0.2), body + Eigen::Vector2d(0.2, 0.2), &seen_by_a);
  }
  MergeEngineOptions options = merge_fixtures::GateOptions();
  options.max_global_searches_per_update = 100;
  options.whole_map_body_radius = body_radius;
  auto engine = std::make_unique<MergeEngine>(options);
  Feed(seen_by_a, *a, engine.get());
  Feed(testing::OfficeWorld(), *b, engine.get());
  return engine;
}

TEST(MergeEngineAmbiguityTest, BodiesOnTheOtherRobotsPathAreNotWallsSeenThrough) {
  SimRobot a, b;
  auto engine = BodiesEngine(MergeEngineOptions().whole_map_body_radius, &a, &b);
  std::string provenance;
  for (int i = 0; i < 3 && !engine->RobotToGlobal("b"); ++i) {
    for (const AlignmentEvent& e : engine->Update().events) {
      if (e.type == AlignmentEventType::kAlignmentAccepted) provenance = e.reason;
    }
  }
  const auto rel = EstimatedRelative(*engine, "a", "b");
  ASSERT_TRUE(rel);
  const Rigid2d error = TrueRelative(a, b).inverse() * *rel;
  EXPECT_LT(error.translation().norm(), 0.05);
  EXPECT_LT(std::abs(error.rotation()), 0.01);
  EXPECT_NE(provenance.find("on the robots' trails"), std::string::npos) << provenance;
}

TEST(MergeEngineAmbiguityTest, CountedAsWallsTheBodiesKeepTheJoinWaiting) {
  SimRobot a, b;
  auto engine = BodiesEngine(0.0, &a, &b);
  int contradicted = 0;
  for (int i = 0; i < 3; ++i) {
    for (const AlignmentEvent& e : engine->Update().events) {
      contradicted += e.reason.find("the whole maps contradict it") != std::string::npos;
    }
  }
  EXPECT_FALSE(engine->RobotToGlobal("b"));
  EXPECT_GE(contradicted, 1);
}

}  // namespace
}  // namespace fleetmap
