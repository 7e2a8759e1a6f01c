// A match found against a part's composite map becomes a graph edge from one node of that part.
// Refined against that node's submap alone (MergeEngineOptions::edge_refine_window, with the
// points that land where that submap saw anything), the edge measures the two submaps; taken
// from the composite, it also carries where the graph placed the composite's other submaps at
// that moment. And which match edges a join leaves in the graph: none twice, and local
// constraints on both sides of it.

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>

#include "map_server/merge/merge_engine.h"
#include "tests/merge/merge_engine_fixtures.h"
#include "tests/merge/merge_test_worlds.h"

namespace fleetmap {
namespace {

using namespace merge_fixtures;

struct EdgeErrors {
  int edges = 0;
  double max_translation = 0.0;  // metres
  double max_rotation = 0.0;     // radians
};

// Robot a's local SLAM turns its heading by `drift` per submap: each submap's contents are right
// in its own frame, its anchor is not. Its submaps overlap, so the composite around any of b's
// submaps holds several of a's, each placed by the drifting chain.
class DriftingChain {
 public:
  explicit DriftingChain(double drift) : a_(RobotA()), b_(RobotB(-1.0)) {
    const testing::SegmentWorld world = testing::OfficeWorld();
    for (const SimRobot* robot : {&a_, &b_}) {
      for (Submap s :
           testing::MakeSubmaps(robot->id, world, robot->path, robot->local_in_world, 10, kDt)) {
        true_anchors_[{robot->id, s.submap_id}] = robot->local_in_world * s.submap_in_local;
        if (robot == &a_) {
          const Rigid2d turn(0.0, 0.0, drift * static_cast<double>(s.submap_id));
          s.submap_in_local = turn * s.submap_in_local;
          for (StampedPose& p : s.scan_poses) p.pose = turn * p.pose;
        }
        submaps_.push_back(std::move(s));
      }
    }
  }

  // Joined by detections of b seen from a, with local constraints between their submaps.
  EdgeErrors CrossEdgeErrors(double edge_refine_window) const {
    MergeEngineOptions options = TestOptions();
    options.edge_refine_window = edge_refine_window;
    MergeEngine engine(options);
    for (const Submap& s : submaps_) EXPECT_TRUE(engine.AddOrUpdateSubmap(s));
    EXPECT_TRUE(engine.AddDetection(Detect(a_, b_, 20, false)));
    EXPECT_TRUE(engine.AddDetection(Detect(a_, b_, 24, false)));
    for (int i = 0; i < 20 && (i == 0 || engine.HasPendingWork()); ++i) engine.Update();
    EXPECT_EQ(engine.PlacedRobots().size(), 2u);
    EdgeErrors errors;
    for (const RelativeEdge& e : engine.graph().edges()) {
      if (e.kind != EdgeKind::kCrossMatch || e.from.robot == e.to.robot) continue;
      const Rigid2d truth = true_anchors_.at(e.from).inverse() * true_anchors_.at(e.to);
      const Rigid2d diff = truth.inverse() * e.to_in_from;
      ++errors.edges;
      errors.max_translation = std::max(errors.max_translation, diff.translation().norm());
      errors.max_rotation =
          std::max(errors.max_rotation, std::abs(NormalizeAngle(diff.rotation())));
    }
    return errors;
  }

 private:
  SimRobot a_, b_;
  std::vector<Submap> submaps_;
  std::map<NodeId, Rigid2d> true_anchors_;
};

TEST(MergeEngineEdgesTest, EdgesRefinedAgainstOneSubmapMeasureThatSubmap) {
  const DriftingChain chain(0.004);  // 0.23 deg per submap
  const EdgeErrors refined = chain.CrossEdgeErrors(0.1);
  ASSERT_GE(refined.edges, 3);
  EXPECT_LE(refined.max_translation, 0.02);
  EXPECT_LE(refined.max_rotation, 0.2 * M_PI / 180);
}

// The same chain without the refinement (window 0): the composite's misplaced submaps reach the
// edges, so the case above is one the refinement has to fix. (The refinement itself is good to
// about 0.15 deg on these 10-scan submaps: 0.06-0.15 deg measured, depending on where it starts.)
TEST(MergeEngineEdgesTest, EdgesFromTheCompositeCarryTheChainsDrift) {
  const DriftingChain chain(0.004);
  const EdgeErrors composite = chain.CrossEdgeErrors(0.0);
  ASSERT_GE(composite.edges, 3);
  EXPECT_GT(composite.max_rotation, 0.3 * M_PI / 180);
}

// Robots a and b joined by two detections, updated until nothing is postponed.
std::unique_ptr<MergeEngine> JoinedByDetections() {
  auto engine = std::make_unique<MergeEngine>(TestOptions());
  const testing::SegmentWorld world = testing::OfficeWorld();
  const SimRobot a = RobotA(), b = RobotB(-1.0);
  Feed(world, a, engine.get());
  Feed(world, b, engine.get());
  EXPECT_TRUE(engine->AddDetection(Detect(a, b, 20, false)));
  EXPECT_TRUE(engine->AddDetection(Detect(a, b, 24, false)));
  for (int i = 0; i < 20 && (i == 0 || engine->HasPendingWork()); ++i) engine->Update();
  EXPECT_EQ(engine->PlacedRobots().size(), 2u);
  return engine;
}

// A join moves the joined part's map into the other's frame in the middle of an update. The
// local constraints that follow in that update match each submap against the other robots' maps:
// drawn where they were before the join, a's submaps found nothing there and were not searched
// again (docs/BENCHMARKS.md, issue 8, session 26).
TEST(MergeEngineEdgesTest, LocalConstraintsAfterAJoinSeeTheJoinedMap) {
  const auto engine = JoinedByDetections();
  std::map<std::string, int> matched;  // robot -> its submaps tied to the other's by a match
  for (const RelativeEdge& e : engine->graph().edges()) {
    if (e.kind == EdgeKind::kCrossMatch && e.from.robot != e.to.robot) ++matched[e.to.robot];
  }
  EXPECT_GE(matched["a"], 3);
  EXPECT_GE(matched["b"], 3);
}

// The match that joined a submap ties it to the node nearest it; its local constraint finds the
// same node again. One measurement must not weigh as two.
TEST(MergeEngineEdgesTest, NoMatchIsInTheGraphTwice) {
  const auto engine = JoinedByDetections();
  std::set<std::pair<NodeId, NodeId>> seen;
  for (const RelativeEdge& e : engine->graph().edges()) {
    if (e.kind != EdgeKind::kCrossMatch && e.kind != EdgeKind::kDetectionMatch) continue;
    EXPECT_TRUE(seen.insert({e.from, e.to}).second)
        << e.from.robot << "/" << e.from.submap << " -> " << e.to.robot << "/" << e.to.submap;
  }
  EXPECT_GE(seen.size(), 6u);
}

}  // namespace
}  // namespace fleetmap
