#ifndef FLEETMAP_MAP_SERVER_MERGE_MERGE_TYPES_H_
#define FLEETMAP_MAP_SERVER_MERGE_MERGE_TYPES_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "map_server/merge/log_odds_canvas.h"
#include "map_server/merge/pose_graph.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// What the merge engine did with a piece of evidence; the provenance of a global map version.
enum class AlignmentEventType {
  kAlignmentAccepted,  // two robots' maps are now joined (robot_b placed relative to robot_a)
  kHypothesis,         // a plausible alignment waiting for a second, independent confirmation
  kRejected,           // evidence that failed a gate (the reason says which)
  kConstraintAdded,    // a detection or match added to the graph between joined robots
  kPending,            // a detection waiting for trajectories/submaps covering its time
  // An accepted alignment undone (robot_b split off): later detections contradict it, or a join
  // on the whole maps is ambiguous over the grown maps.
  kWithdrawn,
};
const char* AlignmentEventTypeName(AlignmentEventType type);

enum class EvidenceKind { kDetection, kCrossMatch, kLoopClosure };

struct AlignmentEvent {
  AlignmentEventType type = AlignmentEventType::kRejected;
  EvidenceKind evidence = EvidenceKind::kDetection;
  std::string robot_a;  // observer / target side
  std::string robot_b;  // observed / source side
  std::vector<int64_t> submaps_b;         // the source robot's submaps used
  std::optional<size_t> detection_index;  // into the engine's detections, for detections
  // robot_b's local frame in robot_a's local frame, as estimated by this evidence.
  std::optional<Rigid2d> local_b_in_local_a;
  double score = 0.0;
  double ambiguity = 0.0;
  double overlap = 0.0;
  double residual = 0.0;  // metres
  std::string reason;
};

// Figures describing the current merged map.
struct MergeQuality {
  int inter_robot_edges = 0;
  double inter_robot_rms_translation = 0.0;  // metres, residuals of inter-robot constraints
  double inter_robot_max_translation = 0.0;
  double inter_robot_rms_rotation = 0.0;  // radians
  // Map consistency among placed robots: cells where two robots both have an opinion, and
  // those where one says wall and the other says free.
  int64_t overlapping_cells = 0;
  int64_t disagreeing_cells = 0;
  double disagreement_fraction() const {
    return overlapping_cells > 0 ? static_cast<double>(disagreeing_cells) / overlapping_cells : 0.0;
  }
};

// The result of MergeEngine::Update().
struct MergeUpdate {
  std::vector<AlignmentEvent> events;
  bool graph_changed = false;  // the placed submaps moved or new ones were placed
  std::vector<NodeId> moved_submaps;
  std::optional<Box2d> changed_region;  // global frame, union of old and new footprints
  std::vector<std::string> placed_robots;
  int solver_iterations = 0;
  MergeQuality quality;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_MERGE_TYPES_H_
