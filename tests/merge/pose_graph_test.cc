#include "map_server/merge/pose_graph.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::IsNearPose;

RelativeEdge Edge(const NodeId& from, const NodeId& to, const Rigid2d& to_in_from, double sigma_t,
                  double sigma_r, double robust = 0.0) {
  RelativeEdge e;
  e.from = from;
  e.to = to;
  e.to_in_from = to_in_from;
  e.translation_sigma = sigma_t;
  e.rotation_sigma = sigma_r;
  e.robust_scale = robust;
  return e;
}

// Two equally weighted measurements of the same relation: the optimum is their mean.
TEST(PoseGraphTest, EqualWeightsAverage) {
  PoseGraph graph;
  const NodeId a{"r1", 0}, b{"r1", 1};
  graph.SetNode(a, Rigid2d());
  graph.SetNode(b, Rigid2d(0.5, 0.5, 0.3));
  graph.SetFixed(a);
  graph.AddEdge(Edge(a, b, Rigid2d(1.0, 0.0, 0.1), 0.1, 0.01));
  graph.AddEdge(Edge(a, b, Rigid2d(1.2, 0.0, 0.1), 0.1, 0.01));
  const SolveSummary summary = graph.Solve();
  ASSERT_TRUE(summary.success);
  EXPECT_THAT(*graph.NodePose(b), IsNearPose(Rigid2d(1.1, 0.0, 0.1), 1e-4, 1e-5));
  EXPECT_THAT(*graph.NodePose(a), IsNearPose(Rigid2d(), 1e-9, 1e-9));
}

// Detaching a robot removes exactly its links to other robots (edges and detections), and keeps
// its own chain and the links among the others.
TEST(PoseGraphTest, DetachRobotRemovesOnlyItsLinksToOthers) {
  PoseGraph graph;
  const NodeId a0{"a", 0}, a1{"a", 1}, b0{"b", 0}, b1{"b", 1}, c0{"c", 0};
  for (const NodeId& n : {a0, a1, b0, b1, c0}) graph.SetNode(n, Rigid2d());
  graph.AddEdge(Edge(a0, a1, Rigid2d(1, 0, 0), 0.1, 0.01));
  graph.AddEdge(Edge(b0, b1, Rigid2d(1, 0, 0), 0.1, 0.01));
  graph.AddEdge(Edge(a1, b0, Rigid2d(1, 0, 0), 0.1, 0.01));
  graph.AddEdge(Edge(c0, a0, Rigid2d(1, 0, 0), 0.1, 0.01));
  graph.AddEdge(Edge(b1, c0, Rigid2d(1, 0, 0), 0.1, 0.01));
  DetectionEdge seen;
  seen.observer = c0;
  seen.observed = b1;
  graph.AddDetection(seen);
  seen.observer = a0;
  seen.observed = c0;
  graph.AddDetection(seen);
  EXPECT_EQ(graph.DetachRobot("b"), 3u);
  ASSERT_EQ(graph.edges().size(), 3u);
  EXPECT_TRUE(graph.edges()[0].from == a0 && graph.edges()[0].to == a1);
  EXPECT_TRUE(graph.edges()[1].from == b0 && graph.edges()[1].to == b1);
  EXPECT_TRUE(graph.edges()[2].from == c0 && graph.edges()[2].to == a0);
  ASSERT_EQ(graph.detections().size(), 1u);
  EXPECT_TRUE(graph.detections()[0].observer == a0);
  EXPECT_EQ(graph.nodes().size(), 5u);
}

// A square loop of consistent edges plus one grossly wrong loop closure with a robust loss:
// the optimum stays at the true square.
TEST(PoseGraphTest, RobustLossIgnoresOutlierEdge) {
  PoseGraph graph;
  std::vector<NodeId> ids;
  std::vector<Rigid2d> truth;
  for (int i = 0; i < 8; ++i) {
    ids.push_back({"r1", i});
    truth.emplace_back(std::cos(i * M_PI / 4) * 3.0, std::sin(i * M_PI / 4) * 3.0, i * M_PI / 4 + M_PI / 2);
    // Start from a perturbed guess.
    graph.SetNode(ids.back(), Rigid2d(truth.back().translation() + Eigen::Vector2d(0.1 * i, -0.05 * i),
                                      truth.back().rotation() + 0.02 * i));
  }
  graph.SetNode(ids[0], truth[0]);
  graph.SetFixed(ids[0]);
  for (int i = 0; i < 8; ++i) {
    const int j = (i + 1) % 8;
    graph.AddEdge(Edge(ids[i], ids[j], truth[i].inverse() * truth[j], 0.02, 0.005));
  }
  graph.AddEdge(Edge(ids[2], ids[6], Rigid2d(1.0, 2.0, 1.0), 0.05, 0.01, 1.0));
  ASSERT_TRUE(graph.Solve().success);
  for (int i = 0; i < 8; ++i) {
    EXPECT_THAT(*graph.NodePose(ids[i]), IsNearPose(truth[i], 0.02, 0.005)) << "node " << i;
  }
}

// A second robot placed by two detections with heading: recovers its known pose.
TEST(PoseGraphTest, DetectionsPlaceSecondRobot) {
  PoseGraph graph;
  const NodeId a{"a", 0}, b{"b", 0};
  const Rigid2d b_truth(4.0, 1.0, 2.0);
  graph.SetNode(a, Rigid2d());
  graph.SetNode(b, Rigid2d(3.0, 0.0, 1.5));
  graph.SetFixed(a);
  for (const Rigid2d& a_robot : {Rigid2d(1, 0, 0.2), Rigid2d(2, 1, -0.4)}) {
    DetectionEdge d;
    d.observer = a;
    d.observed = b;
    d.observer_robot_in_node = a_robot;
    d.observed_robot_in_node = Rigid2d(0.5, 0.2, 0.1);
    const Rigid2d observed = b_truth * d.observed_robot_in_node;
    d.position = a_robot.inverse() * observed.translation();
    d.covariance = Eigen::Matrix2d::Identity() * 1e-4;
    d.relative_heading = NormalizeAngle(observed.rotation() - a_robot.rotation());
    d.heading_variance = 1e-4;
    graph.AddDetection(d);
  }
  ASSERT_TRUE(graph.Solve().success);
  EXPECT_THAT(*graph.NodePose(b), IsNearPose(b_truth, 1e-3, 1e-3));
  for (const EdgeResidual& r : graph.Residuals()) EXPECT_LT(r.translation, 1e-3);
}

}  // namespace
}  // namespace fleetmap
