#ifndef FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_
#define FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

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

  // The score of one pose (nearest cells), e.g. to verify a predicted alignment.
  double ScoreAt(const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose) const;
  // Fraction of points landing on observed target cells: the overlap of the two maps.
  double OverlapAt(const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose) const;

  const ScoreGrid& grid() const { return grid_; }

 private:
  const ScoreGrid& grid_;
  BranchAndBoundOptions options_;
  ScoreGridPyramid pyramid_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_BRANCH_AND_BOUND_MATCHER_H_
