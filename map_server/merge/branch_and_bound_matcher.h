#ifndef FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_
#define FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <queue>
#include <vector>

#include "map_server/merge/score_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// Where to look: poses of the source frame in the target frame within
// center.translation() +- linear_half_extent and center.rotation() +- angular_half_extent.
// An angular half extent >= pi searches the full circle.
struct SearchWindow {
  Rigid2d center;
  Eigen::Vector2d linear_half_extent = Eigen::Vector2d::Constant(1.0);
  double angular_half_extent = M_PI;
};

// Poses too close to `center` are not candidates; used to find the best *distinct* second peak.
struct ExclusionZone {
  Rigid2d center;
  double linear = 0.5;    // metres
  double angular = 0.26;  // radians

  bool Contains(const Rigid2d& pose) const {
    return (pose.translation() - center.translation()).norm() < linear &&
           std::abs(NormalizeAngle(pose.rotation() - center.rotation())) < angular;
  }
};

struct BranchAndBoundOptions {
  int max_levels = 8;  // max-pooled pyramid levels (top block = 2^(levels-1) cells)
  // Angular step so that the farthest point moves by about one cell, capped here (radians).
  double max_angular_step = 0.05;
};

struct MatchCandidate {
  Rigid2d pose;          // source frame in target frame
  double score = 0.0;    // mean per-point score, in [free_penalty, 1]
};

// A lattice pose block under examination: the translations [x, x + 2^level) x [y, y + 2^level)
// at one rotation, with the pyramid's upper bound of their scores.
struct LatticeNode {
  int level = 0;
  int rotation = 0;
  int x = 0;  // first cell offset of the block
  int y = 0;
  float score = 0.0f;
};

// The source points rotated by one lattice angle, as integer target cells at zero offset.
struct LatticeRotation {
  double angle = 0.0;
  std::vector<Eigen::Array2i> cells;
};

// The search lattice of one window: its rotations and its translation extent in cells.
struct SearchLattice {
  std::vector<LatticeRotation> rotations;
  int window_x = 0;
  int window_y = 0;
  int top = 0;  // pyramid level of the first blocks
  double resolution = 0.1;
  Eigen::Vector2d center_translation = Eigen::Vector2d::Zero();
};

class BranchAndBoundMatcher;

// Distinct peaks of a search lattice, best first, one per Next(): the poses that Search would
// return if called again and again with a zone around each answer added to the exclusions, from
// one best-first traversal that keeps its frontier between answers. Asking two whole maps for
// 16 alternatives took 16 searches of 0.3 s each (east_end, session 23); the frontier makes the
// later ones cheap. Keeps a reference to the matcher.
class PeakSearch {
 public:
  // The best lattice pose left scoring above the minimum and outside every exclusion; none when
  // no such pose remains.
  std::optional<MatchCandidate> Next();
  // Rules out poses inside `zone` from now on (typically around the answer just returned).
  void Exclude(const ExclusionZone& zone) { exclusions_.push_back(zone); }

 private:
  friend class BranchAndBoundMatcher;
  struct Lower {
    bool operator()(const LatticeNode& a, const LatticeNode& b) const { return a.score < b.score; }
  };
  PeakSearch(const BranchAndBoundMatcher& matcher, SearchLattice lattice, float min_score,
             std::vector<ExclusionZone> exclusions);

  const BranchAndBoundMatcher& matcher_;
  SearchLattice lattice_;
  float min_score_;
  std::vector<ExclusionZone> exclusions_;
  std::priority_queue<LatticeNode, std::vector<LatticeNode>, Lower> frontier_;
};

// Exhaustive correlative search made fast by branch and bound over a max-pooled pyramid of the
// target's ScoreGrid (as in Hess et al., "Real-time loop closure in 2D LIDAR SLAM"): the answer
// is the best pose on the discrete search lattice, not a local optimum. Keeps a reference to
// the grid, which must outlive the matcher.
class BranchAndBoundMatcher {
 public:
  BranchAndBoundMatcher(const ScoreGrid& grid, const BranchAndBoundOptions& options);

  // The best pose scoring above `min_score`, skipping poses inside any of `exclusions`.
  std::optional<MatchCandidate> Search(const std::vector<Eigen::Vector2d>& source_points,
                                       const SearchWindow& window, double min_score,
                                       const std::vector<ExclusionZone>& exclusions = {}) const;

  // Distinct peaks above `min_score` outside `exclusions`, best first (see PeakSearch).
  PeakSearch Peaks(const std::vector<Eigen::Vector2d>& source_points, const SearchWindow& window,
                   double min_score, const std::vector<ExclusionZone>& exclusions) const;

  // The score of one pose (nearest cells), e.g. to verify a predicted alignment.
  double ScoreAt(const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose) const;
  // Fraction of points landing on observed target cells: the overlap of the two maps.
  double OverlapAt(const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose) const;

  const ScoreGrid& grid() const { return grid_; }

 private:
  friend class PeakSearch;
  // Empty rotations when there is nothing to search.
  SearchLattice MakeLattice(const std::vector<Eigen::Vector2d>& source_points,
                            const SearchWindow& window) const;
  // The blocks of the lattice's top level, each with its bound.
  std::vector<LatticeNode> TopNodes(const SearchLattice& lattice) const;
  float Bound(const SearchLattice& lattice, const LatticeNode& node) const;

  const ScoreGrid& grid_;
  BranchAndBoundOptions options_;
  ScoreGridPyramid pyramid_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_
