#ifndef FLEETMAP_MAP_SERVER_MERGE_POSE_GRAPH_H_
#define FLEETMAP_MAP_SERVER_MERGE_POSE_GRAPH_H_

#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// A node of the global pose graph: one submap anchor of one robot.
struct NodeId {
  std::string robot;
  int64_t submap = 0;
  bool operator<(const NodeId& o) const { return std::tie(robot, submap) < std::tie(o.robot, o.submap); }
  bool operator==(const NodeId& o) const { return robot == o.robot && submap == o.submap; }
};

enum class EdgeKind { kOdometry, kLoopClosure, kCrossMatch, kDetectionMatch };
const char* EdgeKindName(EdgeKind kind);

// `to` seen from `from`: to_in_from = from^-1 * to, with standard deviations.
struct RelativeEdge {
  NodeId from;
  NodeId to;
  Rigid2d to_in_from;
  double translation_sigma = 0.05;  // metres
  double rotation_sigma = 0.01;     // radians
  EdgeKind kind = EdgeKind::kOdometry;
  // Robust loss scale in units of sigma; 0 = plain least squares.
  double robust_scale = 0.0;
};

// A robot detection: the observed robot's centre, seen from the observer, constrains
// observed_node * observed_robot_in_node relative to observer_node * observer_robot_in_node.
struct DetectionEdge {
  NodeId observer;
  NodeId observed;
  Rigid2d observer_robot_in_node;
  Rigid2d observed_robot_in_node;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  // observed centre, observer robot frame
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  std::optional<double> relative_heading;
  double heading_variance = 0.01;
  double robust_scale = 3.0;
};

struct PoseGraphOptions {
  int max_iterations = 50;
  double function_tolerance = 1e-8;
};

struct EdgeResidual {
  size_t index = 0;       // into relative or detection edges
  bool detection = false;
  double translation = 0.0;  // metres
  double rotation = 0.0;     // radians (0 for position-only detections)
  double normalized = 0.0;   // error in units of sigma (Mahalanobis)
};

struct SolveSummary {
  bool success = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::vector<EdgeResidual> residuals;
};

// The global pose graph, solved with Ceres: submap anchors in the global frame, relative edges
// (local SLAM between consecutive submaps, loop closures, cross-robot matches) and detection
// edges, each with a robust loss so a wrong edge cannot bend the map. Solving starts from the
// current estimates, so adding a node and re-solving is incremental in practice.
class PoseGraph {
 public:
  explicit PoseGraph(const PoseGraphOptions& options = PoseGraphOptions()) : options_(options) {}

  void SetNode(const NodeId& id, const Rigid2d& pose_in_global);
  bool HasNode(const NodeId& id) const { return nodes_.count(id) != 0; }
  std::optional<Rigid2d> NodePose(const NodeId& id) const;
  const std::map<NodeId, Rigid2d>& nodes() const { return nodes_; }
  void RemoveRobot(const std::string& robot);
  // Removes every edge (relative or detection) between the robot's nodes and another robot's,
  // keeping its own; indices of the remaining edges shift. Returns how many were removed.
  size_t DetachRobot(const std::string& robot);

  // Returns the edge's index. Edges with a missing node are ignored when solving.
  size_t AddEdge(const RelativeEdge& edge);
  size_t AddDetection(const DetectionEdge& edge);
  // Replaces an edge's measurement (e.g. a re-published submap moved its anchor).
  void UpdateEdge(size_t index, const RelativeEdge& edge) { edges_.at(index) = edge; }
  const std::vector<RelativeEdge>& edges() const { return edges_; }
  const std::vector<DetectionEdge>& detections() const { return detections_; }

  // Nodes held constant (at least one per connected part, to fix its frame).
  void SetFixed(const NodeId& id, bool fixed = true) {
    if (fixed) {
      fixed_.insert(id);
    } else {
      fixed_.erase(id);
    }
  }

  // Optimises every node of the robots in `robots` (all when empty) with the edges among them.
  SolveSummary Solve(const std::set<std::string>& robots = {});

  // Residuals of the current estimate, without solving.
  std::vector<EdgeResidual> Residuals() const;

 private:
  PoseGraphOptions options_;
  std::map<NodeId, Rigid2d> nodes_;
  std::set<NodeId> fixed_;
  std::vector<RelativeEdge> edges_;
  std::vector<DetectionEdge> detections_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_POSE_GRAPH_H_
