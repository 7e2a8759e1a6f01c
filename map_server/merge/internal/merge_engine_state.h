#ifndef FLEETMAP_MAP_SERVER_MERGE_INTERNAL_MERGE_ENGINE_STATE_H_
#define FLEETMAP_MAP_SERVER_MERGE_INTERNAL_MERGE_ENGINE_STATE_H_

// The merge engine's private bookkeeping, shared by its implementation files (merge_engine*.cc).

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "map_server/merge/log_odds_canvas.h"
#include "map_server/merge/match_target.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

inline Box2d Grow(Box2d box, double margin) {
  box.min.array() -= margin;
  box.max.array() += margin;
  return box;
}

// A match's figures in an alignment event.
inline void FillEvent(const MatchResult& r, AlignmentEvent* event) {
  event->score = r.score;
  event->ambiguity = r.ambiguity;
  event->overlap = r.overlap;
  event->residual = r.residual;
  event->reason = r.reason;
}

struct MergeEngine::RobotState {
  explicit RobotState(double resolution) : canvas(resolution) {}
  std::map<int64_t, Submap> submaps;
  // Each submap's observed cells as a box in its own frame (KnownBox), kept so that placing a
  // submap does not scan its grid again: the engine places every submap several times per
  // update.
  std::map<int64_t, std::optional<Box2d>> known_boxes;
  std::optional<Box2d> SubmapBounds(int64_t id, const Rigid2d& submap_to_frame) const {
    const std::optional<Box2d>& box = known_boxes.at(id);
    return box ? std::optional<Box2d>(PlaceBox(*box, submap_to_frame)) : std::nullopt;
  }
  Trajectory trajectory;
  std::optional<NodeId> fixed_node;           // set while this robot roots its component
  int64_t joined_at = 0;                      // when it last joined another component (0: never)
  // Joined on matches alone, with no detection: judged again as the maps grow, at
  // join_reviewed_at finished submaps of its component last (merge_engine_join_review.cc).
  enum class MatchOnlyJoin { kNo, kOnWholeMaps, kOnSubmapMatches };
  MatchOnlyJoin joined_on_matches_alone = MatchOnlyJoin::kNo;
  int join_reviewed_at = 0;
  std::map<int64_t, size_t> odometry_edge;    // by the later submap of the pair
  // The robot's submaps rendered at their graph poses (the frame of its component).
  LogOddsCanvas canvas;
  struct Rendered {
    Rigid2d pose;
    int64_t revision = 0;
  };
  std::map<int64_t, Rendered> rendered;
  int64_t canvas_version = 0;
  std::map<int64_t, std::pair<int64_t, MatchSource>> sources;  // id -> (revision, points)
  std::set<int64_t> cross_queue;                      // finished, awaiting global search
  // id -> component roots searched over, each with how many finished submaps it had then.
  std::map<int64_t, std::map<std::string, int>> cross_tried;
  std::set<int64_t> local_queue;                      // awaiting a local constraint search
  std::set<int64_t> loop_queue;                       // awaiting a loop closure search
};

// A plausible alignment between two components, waiting for a second piece of evidence.
struct MergeEngine::Hypothesis {
  std::string robot_a;
  std::string robot_b;
  Rigid2d local_b_in_local_a;
  std::optional<size_t> detection;
  // For a detection: where robot_b stood in its own local frame at the detection time.
  Eigen::Vector2d observed_in_local = Eigen::Vector2d::Zero();
  std::set<int64_t> submaps_b;
  bool whole_maps = false;  // from matching the whole maps (merge_engine_whole_map_match.cc)
  RelativeEdge edge;  // the match as a graph edge, once the components are joined
  std::optional<DetectionEdge> detection_edge;
  AlignmentEvent event;
  int reviewed_at_submaps = 0;  // finished submaps in both parts when last checked
  // On probation (MergeEngine::probation_): finished submaps in both parts when it began, and
  // the edges that confirmed the alignment then.
  int probation_from = 0;
  std::vector<RelativeEdge> confirmed_by;
};

struct MergeEngine::CachedSubmapTarget {
  int64_t revision = 0;
  int64_t last_used = 0;
  // Shared, so that an edge being refined keeps its target while the cache drops it.
  std::shared_ptr<const MatchTarget> target;
};

// One new submap searched for around its graph pose: against the other joined robots' maps
// there (a local constraint) or against its own robot's older submaps (a loop closure). Planned
// on the engine's thread; `make_target` and the match run on any of the search threads, and
// read only what no one changes meanwhile (canvases, submaps, graph poses).
struct MergeEngine::NearbySearch {
  EdgeKind kind = EdgeKind::kCrossMatch;  // kCrossMatch: local constraint; kLoopClosure
  NodeId submap;
  std::optional<NodeId> from;  // loop closures: the nearest older submap, known before the search
  std::function<std::unique_ptr<MatchTarget>()> make_target;
  const MatchSource* source = nullptr;
  SearchWindow window;
  MatchResult result;  // filled by the search
};

// What refining a match edge against its from-node's submap needs (MergeEngine::MatchedEdge),
// gathered on the engine's thread so that the refinement can run on any thread.
struct MergeEngine::EdgeToRefine {
  RelativeEdge edge;  // as the match against the composite map measured it
  std::shared_ptr<const MatchTarget> from_target;  // null: kept as measured
  const OccupancyGrid* from_grid = nullptr;
  const MatchSource* from_walls = nullptr;
  const MatchSource* to_source = nullptr;
  Box2d to_box;
};

struct MergeEngine::CachedTarget {
  std::string stamp;  // member robots and their canvas versions when built
  std::unique_ptr<MatchTarget> target;
};

// A submap searched over the whole map of another part: its points turned about their
// centroid (so that the window only has to cover the target map), the window over that map.
struct MergeEngine::GlobalSearch {
  MatchSource source;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  SearchWindow window;
};

// A global search run ahead (MergeEngine::SearchCrossMatchesAhead).
struct MergeEngine::SearchedAhead {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // GlobalSearch::centroid
  MatchResult result;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_INTERNAL_MERGE_ENGINE_STATE_H_
