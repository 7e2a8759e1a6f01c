#ifndef FLEETMAP_ROBOT_AGENT_SLAM_LOOP_CLOSURE_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_LOOP_CLOSURE_H_

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/slam/pose_graph_2d.h"
#include "shared/core/rigid2d.h"
#include "shared/matching/correlative_search.h"
#include "shared/matching/match_grid.h"
#include "shared/matching/match_grid_pyramid.h"
#include "shared/matching/pose_refinement.h"
#include "shared/matching/seen_from_behind.h"

namespace fleetmap {

struct LoopClosureOptions {
  bool enabled = true;
  // Loop-closure targets: one distance grid per submap, in the submap frame. They remember the
  // space their scans saw, so that a node's returns where the submap saw nothing (the far side
  // of a box, round a corner) neither count against the true match nor for a wrong one.
  MatchGridOptions grid = DefaultGrid();
  int pyramid_levels = 7;
  // Returns farther than this stay out of the targets and the searches (metres).
  float max_range = 15.0f;
  // The branch-and-bound search uses one point per voxel of this size; refinement uses all.
  float search_voxel_size = 0.15f;
  // Nodes whose scan faces one direction only (a plain corridor: less than this share of surface
  // normals across it, see NormalScatter) are not searched: their matches slide along the axis.
  double min_observed_normals = 0.03;
  // Finished submaps whose distance grid and pyramid stay in memory (about 5 MB each at 5 cm
  // with 15 m returns); the others keep only their scans and are rebuilt when a search needs
  // them again. Without a bound the targets alone took 250 MB on the intel lab (71 submaps);
  // searches only reach the few submaps near the robot, so a handful covers them. 0 keeps all.
  int max_cached_targets = 6;
  // Every n-th node is searched against the finished submaps near it.
  int search_every_nodes = 4;
  // Submaps this recent (by id, relative to the node's own) are left to the local constraints.
  int min_submap_gap = 2;
  // Only submaps whose centre lies this close to the node's current estimate are searched.
  double max_search_distance = 10.0;
  // ... and of those, only the nearest few (the search dominates the cost).
  int max_submaps_per_search = 3;
  // Window around the current estimate: search.linear_window at most, less when the target
  // submap was tied to the graph recently: min_linear_window + linear_window_per_metre * the
  // travel since the target's last loop closure (or since it was built). A window much wider
  // than the drift only adds ways to match a repeating structure (doors, pillars) one period off.
  CorrelativeSearchOptions search = DefaultSearch();
  double min_linear_window = 3.5;
  double linear_window_per_metre = 0.02;
  PoseRefinementOptions refinement = DefaultRefinement();
  // Strict gates: a wrong loop closure hurts more than a missed one. Score and inliers are over
  // the node's points that land where the submap saw something; at least min_observed_fraction
  // of them must.
  double min_refined_score = 0.65;
  double min_inlier_fraction = 0.8;
  double min_observed_fraction = 0.6;
  // A match that sees more than this share of the submap's walls (under the node's returns)
  // from the side the submap never saw is wrong whatever it scores (see WallsSeenFromBehind).
  double max_seen_from_behind = 0.5;
  SeenFromBehindOptions seen_from_behind;
  // A match only becomes a constraint once at least `min_agreeing` matches of nodes searched
  // within `candidate_lifetime_nodes` (itself included) imply the same correction of the current
  // estimate, within these tolerances: wrong matches (repeating structure, partial overlap)
  // scatter, right ones agree because drift is locally rigid.
  int min_agreeing = 3;
  int candidate_lifetime_nodes = 60;
  double agreement_translation = 0.2;
  double agreement_rotation = 0.035;
  // Pose graph: local constraints (node to its submap, node to the previous node) come from the
  // scan matcher and are trusted; loop closures carry a Huber loss. The local translation sigma
  // is what lets DropInconsistentLoops see wrong closures: at 0.02 m per node a few agreeing
  // matches one box width (0.5 m) off bent the chain over a few metres until their residuals
  // fell under max_loop_residual_translation (tests/slam/loop_closure_exact_test.cc); much
  // stiffer (0.005 m) and real drift (aces) no longer fits the chain.
  double local_translation_sigma = 0.01;
  double local_rotation_sigma = 0.005;
  double loop_translation_sigma = 0.05;
  double loop_rotation_sigma = 0.01;
  double loop_robust_scale = 1.0;
  // After an optimisation, loop closures still this far from the solution are dropped as wrong
  // matches and the graph is solved again without them.
  double max_loop_residual_translation = 0.3;
  double max_loop_residual_rotation = 0.05;
  // The graph is optimised when new loop closures arrived and this many nodes were added since
  // the last optimisation.
  int optimize_every_nodes = 60;
  PoseGraphOptions graph;

  static MatchGridOptions DefaultGrid();
  static CorrelativeSearchOptions DefaultSearch();
  static PoseRefinementOptions DefaultRefinement();
};

// Cartographer-style global SLAM over the local SLAM's output: keeps the scan nodes and the
// submaps they were inserted into, searches recent nodes against older finished submaps with the
// branch-and-bound matcher, and optimises a pose graph over submap anchors and nodes. The local
// frontend keeps running in its own (drifting) local frame; this class maps local poses to the
// corrected ("global", still the robot's map frame) ones.
class LoopClosure {
 public:
  explicit LoopClosure(const LoopClosureOptions& options = LoopClosureOptions());
  LoopClosure(const LoopClosure&) = delete;
  LoopClosure& operator=(const LoopClosure&) = delete;

  // A scan inserted into submap `submap_id` (anchored at `submap_in_local`) at `robot_in_local`;
  // points in the robot frame. Nodes come in time order and submap ids never go back. Returns
  // true when the pose graph was optimised (corrections changed).
  bool AddNode(double timestamp, const std::vector<Eigen::Vector2f>& points_in_robot,
               const Rigid2d& robot_in_local, int64_t submap_id, const Rigid2d& submap_in_local);
  // End of input: optimises once more if loop closures are pending. Returns true when it did.
  bool Finish();

  // local -> corrected map frame at `timestamp`, interpolated between the neighbouring nodes.
  Rigid2d CorrectionAt(double timestamp) const;
  // The corrected anchor of a submap; empty for unknown ids.
  std::optional<Rigid2d> SubmapInGlobal(int64_t submap_id) const;

  int64_t nodes() const { return static_cast<int64_t>(nodes_.size()); }
  int64_t searches() const { return searches_; }
  int64_t candidates() const { return candidate_count_; }
  int64_t loop_constraints() const { return static_cast<int64_t>(loops_.size()); }
  int64_t optimizations() const { return optimizations_; }
  int64_t dropped_loops() const { return dropped_; }
  // Finished submaps whose search targets are in memory now, and how often one was rebuilt.
  int cached_targets() const { return cached_targets_; }
  int64_t target_rebuilds() const { return target_rebuilds_; }

 private:
  struct Node {
    double timestamp;
    Rigid2d local;
    Rigid2d global;
    int submap;  // index into submaps_
    double travel;  // metres along the local trajectory since the first node
  };
  // A scan as it went into a submap's grid: replaying these rebuilds the grid exactly.
  struct InsertedScan {
    std::vector<Eigen::Vector2f> points;  // robot frame
    Rigid2d robot_in_submap;
  };
  struct SubmapEntry {
    int64_t id = 0;
    Rigid2d local;
    Rigid2d global;
    // Shared with the searches running on them, so that the cache may drop them meanwhile.
    std::shared_ptr<MatchGrid> grid;  // null while a finished submap is out of the cache
    std::shared_ptr<const MatchGridPyramid> pyramid;  // set when finished and cached
    std::vector<InsertedScan> scans;
    bool finished = false;  // a loop-closure target: ended with at least one point
    uint64_t last_used = 0;  // search count when last searched, for the cache
    Eigen::Vector2d centre_sum = Eigen::Vector2d::Zero();  // of node positions, submap frame
    int node_count = 0;
    double linked_travel = 0.0;  // node travel when the submap was last built on or loop-closed
  };
  struct Loop {
    int node;
    int submap;
    Rigid2d node_in_submap;
    bool accepted = false;
  };

  int SubmapIndex(int64_t submap_id, const Rigid2d& submap_in_local);
  // The finished submap `index` with its grid and pyramid in memory (rebuilt from its scans if
  // they were dropped); drops the least recently used others beyond max_cached_targets.
  const SubmapEntry& Target(size_t index);
  void SearchLoops(int node, const std::vector<Eigen::Vector2f>& points_in_robot);
  // One node's scan searched against one finished submap.
  struct Search {
    std::shared_ptr<const MatchGrid> grid;
    std::shared_ptr<const MatchGridPyramid> pyramid;
    Rigid2d guess;  // the node in the submap frame, by the current estimate
    CorrelativeSearchOptions window;
  };
  // The node's pose in the submap when the match passes every gate (reads only its arguments
  // and options_: searches run concurrently).
  std::optional<Rigid2d> Match(const std::vector<Eigen::Vector2f>& points,
                               const std::vector<Eigen::Vector2f>& search_points,
                               const Search& search) const;
  // Moves candidates that enough others agree with into loops_, and forgets old ones.
  void ConfirmCandidates();
  bool Agree(const Loop& a, const Loop& b) const;
  bool Optimize();
  bool Solve();
  // Removes loop closures the solution disagrees with; returns how many.
  int DropInconsistentLoops();
  Rigid2d NodeCorrection(size_t node) const;

  const LoopClosureOptions options_;
  std::vector<Node> nodes_;
  std::vector<SubmapEntry> submaps_;
  std::map<int64_t, int> submap_index_;
  std::vector<Loop> loops_;
  std::vector<Loop> candidates_;
  size_t loops_at_last_optimization_ = 0;
  size_t nodes_at_last_optimization_ = 0;
  int64_t searches_ = 0;
  int64_t optimizations_ = 0;
  int64_t dropped_ = 0;
  int64_t candidate_count_ = 0;
  int cached_targets_ = 0;
  int64_t target_rebuilds_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_LOOP_CLOSURE_H_
