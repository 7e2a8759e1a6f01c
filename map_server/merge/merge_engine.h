#ifndef FLEETMAP_MAP_SERVER_MERGE_MERGE_ENGINE_H_
#define FLEETMAP_MAP_SERVER_MERGE_MERGE_ENGINE_H_

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "map_server/merge/log_odds_canvas.h"
#include "map_server/merge/match_target.h"
#include "map_server/merge/merge_engine_options.h"
#include "map_server/merge/merge_types.h"
#include "map_server/merge/pose_graph.h"
#include "map_server/merge/trail_walls.h"
#include "map_server/merge/whole_map_walls.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/robot_detection.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

class ThreadPool;

// Places every robot's submaps in one global frame and keeps the merged map: alignment from
// detections (heading resolved by correlative search), alignment from cross-robot submap
// matching (strict gates), a robust pose graph (Ceres), incremental rendering and quality
// figures. Pure: no I/O. Not thread-safe: the server's merge worker owns one and feeds it.
// Update() runs the searches that do not depend on each other on search_threads threads and
// returns when they are done; the answers do not depend on how many.
class MergeEngine {
 public:
  explicit MergeEngine(const MergeEngineOptions& options = MergeEngineOptions());
  ~MergeEngine();
  MergeEngine(const MergeEngine&) = delete;
  MergeEngine& operator=(const MergeEngine&) = delete;

  // Input. Each returns false with a message for invalid data (nothing is changed then).
  bool AddOrUpdateSubmap(const Submap& submap, std::string* error = nullptr);
  bool SetTrajectory(const std::string& robot, const Trajectory& trajectory,
                     std::string* error = nullptr);
  bool AddDetection(const RobotDetection& detection, std::string* error = nullptr);
  // A robot whose start is known (e.g. given at registration): its local frame sits at
  // `local_in_global`, held fixed. Robots with known placements define the global frame; call
  // before the robot's first submap is folded in, and before any robot of unknown start has
  // been folded in (false otherwise).
  bool SetKnownPlacement(const std::string& robot, const Rigid2d& local_in_global,
                         std::string* error = nullptr);

  // Whether joins on matches alone wait on probation for the maps to grow
  // (MergeEngineOptions::match_join_probation_growth; on when that is). Off, what is held is
  // judged at the next Update() on the maps as they are. For when no growth would come to end
  // the wait: a rebuild from everything stored, while it folds in; uploads that have settled.
  void HoldMatchOnlyJoins(bool hold) { hold_match_only_joins_ = hold; }

  // Folds everything received since the last call into the graph and the map.
  MergeUpdate Update();
  // True while searches are waiting that the per-Update() work bounds postponed: call Update()
  // again (when idle) to finish them.
  bool HasPendingWork() const;

  // The robot's local map frame in the global frame; nothing while the robot is unplaced.
  // The first robot to send a submap defines the global frame. The frame is the one the robot's
  // newest submap implies: it places the robot's latest poses, and differs from where the robot
  // started by the local SLAM drift since.
  std::optional<Rigid2d> RobotToGlobal(const std::string& robot) const;
  // The robot's local map frame as its first submap places it: where the robot started.
  std::optional<Rigid2d> RobotStartToGlobal(const std::string& robot) const;
  // Global poses of every placed submap.
  std::map<NodeId, Rigid2d> SubmapPoses() const;
  std::vector<std::string> PlacedRobots() const;
  const std::string& reference_robot() const { return reference_robot_; }

  // The fused map of the placed robots inside `box` (all when absent) at `resolution`.
  std::optional<OccupancyGrid> RenderGlobalMap(const std::optional<Box2d>& box, double resolution,
                                               std::string* error = nullptr) const;
  // Residuals and map consistency over the whole placed map (or a region).
  MergeQuality Quality(const std::optional<Box2d>& region = std::nullopt) const;

  const PoseGraph& graph() const { return graph_; }
  // Global searches run when their turn came rather than ahead: all of them without
  // search_ahead, else those over a part a join earlier in the same update had changed.
  int64_t global_searches_in_turn() const { return global_searches_in_turn_; }
  const std::vector<RobotDetection>& detections() const { return detections_; }

 private:
  struct RobotState;
  struct Hypothesis;
  struct CachedTarget;
  struct CachedSubmapTarget;
  struct NearbySearch;
  struct EdgeToRefine;
  struct GlobalSearch;
  struct SearchedAhead;
  struct TimedPose {
    int64_t host_submap;
    Rigid2d robot_in_node;
  };
  struct SeenPositions {
    Eigen::Vector2d in_observer_frame;  // the detected position, in the observer's component
    Eigen::Vector2d in_observed_frame;  // the seen robot's own position, in its component
  };
  struct DetectionVotes {
    int agreeing = 0;
    int contradicting = 0;
  };
  // Some robots of one component, whose maps are judged together (e.g. a component without the
  // robot whose join is reviewed).
  using Part = std::vector<std::string>;
  struct HeadingPrior {
    double heading;  // the seen robot's component frame in the observer's, radians
    double sigma;
  };

  // merge_engine.cc
  RobotState& Robot(const std::string& id);
  void SyncNodes(MergeUpdate* update);
  bool Solve(MergeUpdate* update);
  void RefreshCanvases(MergeUpdate* update);
  bool IsPlaced(const std::string& robot) const;
  std::string Root(const std::string& robot) const;
  std::vector<std::string> Members(const std::string& root) const;
  // Returns the robots whose component moved into the other's frame.
  std::vector<std::string> JoinComponents(const std::string& root_a, const std::string& root_b,
                                          const Rigid2d& b_in_a);
  std::optional<Rigid2d> LocalToFrame(const std::string& robot) const;

  // merge_engine_alignment.cc
  void ProcessDetections(MergeUpdate* update);
  void ProcessDetection(size_t index, MergeUpdate* update, bool* keep_pending);
  void ProcessCrossMatches(MergeUpdate* update);
  // merge_engine_cross_ahead.cc
  GlobalSearch PrepareGlobalSearch(const std::string& robot, int64_t submap,
                                   const MatchTarget& target);
  // The global searches ProcessCrossMatches is about to run, as they stand before it changes
  // anything, run ahead side by side. Keyed by what a search depends on: the searched submap
  // (robot, id) and the map searched (the part's root and CanvasStamp, the key the part's cached
  // Target is built for). A join changes the stamp, so a search over the joined part's new map
  // finds nothing here and runs again.
  using CrossKey = std::tuple<std::string, int64_t, std::string, std::string>;
  std::map<CrossKey, SearchedAhead> SearchCrossMatchesAhead();
  // merge_engine_nearby.cc: local constraints and loop closures, searched side by side.
  void ProcessNearbyMatches(MergeUpdate* update);
  void PlanLocalConstraints(std::vector<NearbySearch>* searches);
  // merge_engine_withdraw.cc
  // Splits off the robot that the most detections contradict, when the gates say so; true if any.
  bool ReviewJoins(MergeUpdate* update);
  void Withdraw(const std::string& robot, EvidenceKind evidence, const std::string& reason,
                MergeUpdate* update);
  // merge_engine_join_review.cc
  // Splits off the robot joined last on matches alone (no detection) whose map, judged again
  // against the robots it joined now that the maps have grown, fits elsewhere as well; true if
  // it did.
  bool ReviewMatchOnlyJoins(MergeUpdate* update);
  // Detections between the robot and the other members of its component, judged at the
  // current poses.
  DetectionVotes VotesWithin(const std::string& robot) const;
  // merge_engine_motion.cc
  std::optional<SeenPositions> PositionsAt(const RobotDetection& detection) const;
  std::optional<HeadingPrior> HeadingFromMotion(size_t detection_index) const;
  // merge_engine_ambiguity.cc
  // Whether a match-only join of the parts rooted at root_a and root_b at `b_in_a` is
  // unambiguous over their whole maps. The answer is kept while neither part's map changes, for
  // alignments that agree with it.
  struct WholeMapVerdict {
    std::optional<std::string> ambiguity;  // why not; empty when unambiguous
    std::string note;  // for the provenance: the join's own count, what the walls ruled out
  };
  // `max_refuted`: most alternatives the walls may rule out (MaxRefuted: per kind of join).
  WholeMapVerdict WholeMapAmbiguity(const std::string& root_a, const std::string& root_b,
                                    const Rigid2d& b_in_a, int max_refuted);
  // `consistent_competes`: whether an alignment scoring less over all of b's points, but as
  // consistent where it overlaps a's map, competes with the join (twins always do).
  WholeMapVerdict SearchWholeMaps(const Part& part_a, const Part& part_b, const Rigid2d& b_in_a,
                                  int max_refuted, bool consistent_competes = true) const;
  int MaxRefuted(const Hypothesis& h) const;
  // Where the robots of a part drove (scan positions, its component's frame).
  std::vector<Eigen::Vector2d> TrailPositions(const Part& members) const;
  // Where the part's robots drove, widened by a body (whole_map_body_radius).
  TrailMask PartTrails(const Part& members) const;
  WallCountOptions WholeMapWallCounting() const;
  // merge_engine_whole_map_match.cc
  OccupancyGrid RenderPart(const Part& members, double resolution) const;
  MatchTargetOptions WholeMapMatchOptions() const;
  std::vector<std::pair<std::string, std::string>> WholeMapMatchesDue() const;
  void ProcessWholeMapMatches(MergeUpdate* update);
  // merge_engine_loops.cc
  void PlanLoopClosures(std::vector<NearbySearch>* searches);
  // merge_engine_probation.cc
  // Whether a join like `h` waits on probation at all: on matches alone, while held.
  bool ProbationApplies(const Hypothesis& h) const;
  // Whether `h`, a join passing every gate with `confirmed_by` (the edges it would be accepted
  // with), must wait on probation first (noting it when it starts); false, with the probation
  // added to its reason, when it is over or not needed.
  bool HeldOnProbation(Hypothesis* h, const std::vector<RelativeEdge>& confirmed_by,
                       MergeUpdate* update);
  // Whether `h` agrees with an alignment on probation the maps have not yet grown enough to end.
  bool ProbationRunning(const Hypothesis& h) const;
  // With HoldMatchOnlyJoins(false): each alignment held is judged again now over the whole
  // maps, and accepted with the evidence that confirmed it if it passes.
  void JudgeHeldAlignments(MergeUpdate* update);
  // Whether a and b put b's part at the same place in a's (both between the same two parts).
  bool SameAlignment(const Hypothesis& a, const Hypothesis& b) const;
  void Consider(Hypothesis hypothesis, MergeUpdate* update);
  bool Verify(const Hypothesis& hypothesis, std::vector<RelativeEdge>* edges);
  // Pending submap-match hypotheses checked again once the maps have grown.
  void ReviewMatchHypotheses(MergeUpdate* update);
  // Whether more than verify_max_seen_before of submap `id`'s walls lie on cells that `seen`
  // (submaps of the same robot) observed.
  bool MostlySeenBefore(const std::string& robot, int64_t id, const std::set<int64_t>& seen) const;
  // The share of submap `id` of `robot`'s walls that land, placed at `submap_to_frame`, on cells
  // the part rooted at `root` observed.
  double ShareOnPart(const std::string& robot, int64_t id, const Rigid2d& submap_to_frame,
                     const std::string& root) const;
  int FinishedSubmaps(const std::string& root) const;
  // The roots of the parts other than `robot`'s that hold a map.
  std::set<std::string> OtherRoots(const std::string& robot) const;
  // Whether a submap is due a (new) global search over `root`'s map, given the roots it was
  // searched over and how many finished submaps each had then (cross_retry_growth).
  bool CrossSearchDue(const std::map<std::string, int>& tried, const std::string& root) const;
  void Accept(const Hypothesis& hypothesis, const std::vector<RelativeEdge>& extra,
              MergeUpdate* update);
  std::optional<TimedPose> PoseAtTime(const std::string& robot, double time) const;
  // Members and canvas versions of a component: changes whenever its map does.
  std::string CanvasStamp(const std::string& root) const;
  std::string PartStamp(const Part& members) const;
  static std::string PartKey(const Part& members);
  // The whole map of a component (cached), or a freshly built crop of it around `box`.
  const MatchTarget& Target(const std::string& root);
  std::unique_ptr<MatchTarget> CroppedTarget(const std::string& root, const std::string& excluded,
                                             const Box2d& box) const;
  Rigid2d FrameTransform(const Hypothesis& hypothesis) const;
  bool Agree(const Hypothesis& a, const Hypothesis& b) const;
  // The stored detections between h's two parts, judged at h's alignment.
  DetectionVotes DetectionsAbout(const Hypothesis& h) const;
  // A robot's pose at `time` in its component's frame; empty without a pose then.
  std::optional<Rigid2d> RobotInComponent(const std::string& robot, double time) const;
  // Mahalanobis distance of a detection to the observer and observed poses (one frame), over
  // position (its covariance plus detection_sigma_floor) and, when measured, relative heading.
  double DetectionDistance(const RobotDetection& d, const Rigid2d& observer, const Rigid2d& observed) const;
  const MatchSource& SubmapSource(const std::string& robot, int64_t submap_id);
  std::optional<NodeId> NearestNode(const std::string& root, const std::string& excluded,
                                    const Eigen::Vector2d& point_in_frame) const;
  RelativeEdge MatchEdge(const NodeId& from, const NodeId& to, EdgeKind kind) const;
  // The edge of a match placing submap `to` at `to_in_frame` in the frame of `from`'s part.
  RelativeEdge MatchedEdge(const NodeId& from, const NodeId& to, const Rigid2d& to_in_frame,
                           EdgeKind kind);
  // MatchedEdge in two steps: what it needs gathered (engine thread), then the refinement
  // (any thread).
  EdgeToRefine PrepareMatchedEdge(const NodeId& from, const NodeId& to, const Rigid2d& to_in_frame,
                                  EdgeKind kind);
  RelativeEdge RefineMatchedEdge(const EdgeToRefine& prepared) const;
  std::shared_ptr<const MatchTarget> SubmapTarget(const NodeId& id);
  // Whether a match edge from `from` to `to` is in the graph already.
  bool HasMatchEdge(const NodeId& from, const NodeId& to) const;

  const MergeEngineOptions options_;
  std::map<std::string, std::unique_ptr<RobotState>> robots_;
  std::string reference_robot_;
  std::map<std::string, std::string> root_;  // robot -> root robot of its component
  std::map<std::string, Rigid2d> known_placements_;
  std::string known_root_;  // the first robot with a known placement
  PoseGraph graph_;
  bool graph_dirty_ = false;
  std::unique_ptr<ThreadPool> search_pool_;
  std::vector<RobotDetection> detections_;
  std::vector<size_t> pending_detections_;
  std::set<size_t> pending_reported_;
  // Detections whose heading search failed between two parts, with the number of tries: judged
  // again when a finished submap of either robot near their time arrives (at full speed a
  // detection often reaches the server before the submaps that show the meeting).
  std::map<size_t, int> retry_detections_;
  std::vector<Hypothesis> hypotheses_;
  // Match-only alignments on probation, each with when it started (Hypothesis::probation_from).
  std::vector<Hypothesis> probation_;
  bool hold_match_only_joins_ = true;  // HoldMatchOnlyJoins()
  int64_t joins_ = 0;
  bool review_joins_ = false;  // a detection contradicted its robots' joined map
  std::map<std::string, CachedTarget> targets_;
  // The last few submaps refined against alone (MatchedEdge), least recently used dropped first:
  // one target per submap of a 400-submap graph would hold 450 MB.
  std::map<NodeId, CachedSubmapTarget> submap_targets_;
  int64_t submap_target_uses_ = 0;
  int64_t global_searches_in_turn_ = 0;
  struct CachedAmbiguity {
    std::string stamp;
    Rigid2d b_in_a;
    WholeMapVerdict answer;
  };
  std::map<std::pair<std::string, std::string>, CachedAmbiguity> ambiguities_;
  // Finished submaps of both parts when their whole maps were last matched (by sorted roots).
  std::map<std::pair<std::string, std::string>, int> whole_map_tried_;
  // Each part's own symmetries (map_symmetries.h) at its canvas stamp: many joins are checked
  // against one part's map between two of its changes. Filled by SearchWholeMaps, which only
  // WholeMapAmbiguity calls (never from the search threads).
  struct CachedSymmetries {
    std::string stamp;
    std::vector<Rigid2d> moves;
  };
  mutable std::map<std::string, CachedSymmetries> symmetries_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_MERGE_ENGINE_H_
