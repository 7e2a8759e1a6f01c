#ifndef FLEETMAP_MAP_SERVER_MERGE_MATCH_TARGET_H_
#define FLEETMAP_MAP_SERVER_MERGE_MATCH_TARGET_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "map_server/merge/branch_and_bound_matcher.h"
#include "map_server/merge/score_grid.h"
#include "map_server/merge/pose_refiner.h"
#include "map_server/merge/sided_distance_field.h"
#include "shared/core/likelihood_field.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

struct MatchTargetOptions {
  ScoreGridOptions grid;
  BranchAndBoundOptions search;
  PoseRefinerOptions refine;
  double fine_field_max_distance = 0.3;  // metres, distance field used for refinement
  double source_voxel = 0.1;             // coarse source points: one per this square
  size_t max_source_points = 600;
  size_t max_fine_points = 2000;
};

// Acceptance gates of one match; strict by default so that a wrong merge is never accepted.
struct MatchGates {
  double min_score = 0.55;          // mean per-point correlative score at the best pose
  double max_ambiguity = 0.85;      // best distinct second peak / best
  ExclusionZone distinct{Rigid2d(), 0.5, 0.26};  // what counts as a distinct peak
  double min_overlap = 0.5;         // source wall points landing on observed target cells
  double min_inlier_fraction = 0.5;  // after refinement, within refine.inlier_distance
  int min_points = 60;              // source wall points after filtering
  // Judge score and inliers only over the source points landing on observed target cells
  // (min_overlap still says how many must). For searches around a known position (a detection,
  // a predicted pose), where the source map reaching past the target's is expected: averaged
  // over all points, the score could never exceed the overlap, so the score gate would
  // silently demand an overlap well above min_overlap.
  bool judge_overlap_only = false;
};

// The same gates with their minimums (score, points) off: to judge a fit whatever it scores.
MatchGates WithoutMinimums(MatchGates gates);

// A source map prepared for matching: wall points in the source frame, thinned, each with the
// side its wall was seen from (unit normal towards free space; zero when seen from both sides).
struct MatchSource {
  std::vector<Eigen::Vector2d> coarse;
  std::vector<Eigen::Vector2d> fine;
  std::vector<Eigen::Vector2d> coarse_normals;  // one per coarse point
  std::vector<Eigen::Vector2d> fine_normals;    // one per fine point
};
MatchSource MakeMatchSource(const OccupancyGrid& grid, const Rigid2d& grid_to_source,
                            const MatchTargetOptions& options);
// Moves the points (and turns the normals) of `source` by `t`.
void TransformSource(const Rigid2d& t, MatchSource* source);
// Appends `part`'s points to `source`.
void AppendSource(const MatchSource& part, MatchSource* source);
// Keeps the points of `source` that land, at `source_to_grid`, on cells `grid` observed.
void KeepPointsSeenBy(const OccupancyGrid& grid, const Rigid2d& source_to_grid,
                      MatchSource* source);
// Keeps one point per voxel and at most as many points as MakeMatchSource keeps; `fine_voxel`
// is the fine points' voxel size.
void ThinSource(double fine_voxel, const MatchTargetOptions& options, MatchSource* source);

struct MatchResult {
  bool found = false;     // some pose scored above the gate's minimum
  bool accepted = false;  // every gate passed
  std::string reason;     // why not accepted, or a summary when accepted
  Rigid2d pose;           // source frame in target frame (refined)
  double score = 0.0;
  double second_score = 0.0;  // best distinct peak scoring >= max_ambiguity * score, else 0
  double ambiguity = 0.0;     // second_score / score
  double overlap = 0.0;
  double inlier_fraction = 0.0;
  double residual = 0.0;  // mean distance of inlier points to target walls (metres)
  // The same two figures over the source points landing on observed target cells only.
  double overlap_score = 0.0;
  double overlap_inlier_fraction = 0.0;
};

// A target map (in its own frame) ready for global and local searches: the coarse scoring
// grid with its branch-and-bound pyramid, and a fine distance field for refinement.
class MatchTarget {
 public:
  MatchTarget(const OccupancyGrid& target, const MatchTargetOptions& options);
  MatchTarget(const MatchTarget&) = delete;
  MatchTarget& operator=(const MatchTarget&) = delete;

  bool empty() const { return grid_.empty() || grid_.num_occupied() == 0; }
  // Bounds of the target grid (target frame).
  Eigen::Vector2d min_corner() const { return grid_.origin(); }
  Eigen::Vector2d max_corner() const {
    return grid_.origin() + grid_.resolution() * Eigen::Vector2d(grid_.width(), grid_.height());
  }

  // Search, check ambiguity, refine, apply the gates.
  MatchResult Match(const MatchSource& source, const SearchWindow& window,
                    const MatchGates& gates) const;

  // Scores a given pose without searching (same figures as Match, no ambiguity).
  MatchResult Evaluate(const MatchSource& source, const Rigid2d& pose, const MatchGates& gates) const;
  // Every pose of a source centred on its centroid whose centroid lands on this target's grid,
  // at every heading: where to look for a whole map or a submap anywhere on this one.
  SearchWindow Everywhere() const;
  // The best fit within a cell and 0.01 rad of `pose` (a lattice pose of PeaksOutside can be that
  // far off its peak), whatever it scores; `pose` itself when nothing scores.
  Rigid2d BestFitNear(const MatchSource& source, const Rigid2d& pose,
                      const MatchGates& gates) const;

  // The lattice poses in `window` outside every one of `zones` scoring above `min_score`, best
  // first, one distinct peak at a time (PeakSearch): to ask whether anything else explains the
  // source nearly as well as a given alignment. Keeps a reference to this target.
  PeakSearch PeaksOutside(const MatchSource& source, const SearchWindow& window, double min_score,
                          const std::vector<ExclusionZone>& zones) const;
  // How many of `points` (source frame) land, at `pose`, in space the target saw free and away
  // from its walls (beyond twice the score grid's sigma): walls the target's scans went through.
  int ContradictionsAt(const std::vector<Eigen::Vector2d>& points, const Rigid2d& pose) const;
  // The same, with the points cut into square tiles of `tile` metres (source frame) and each
  // tile moved on its own, by whole cells along x and y, to where it crosses least: walls a
  // rigid pose misplaces by the maps' own drift (local SLAM's loops over a long corridor) are
  // not counted, walls standing across the other's free space are. A tile moves at most
  // `window_per_metre` times its centre's distance from the points' centroid, and at most
  // `window`: drift grows away from where an alignment fits, and an alignment off as a whole is
  // not forgiven. `window` 0 is ContradictionsAt.
  int LocallyFittedContradictionsAt(const std::vector<Eigen::Vector2d>& points, const Rigid2d& pose,
                                    double tile, double window, double window_per_metre) const;

 private:
  MatchResult EvaluateWithScore(const MatchSource& source, const Rigid2d& pose,
                                const MatchGates& gates, double score) const;

  MatchTargetOptions options_;
  ScoreGrid grid_;
  std::unique_ptr<BranchAndBoundMatcher> matcher_;
  std::shared_ptr<const LikelihoodField> fine_field_;
  // The refinement matches wall faces to faces seen from the same side (SidedDistanceField,
  // built around each match from this copy of the target).
  OccupancyGrid target_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_MATCH_TARGET_H_
