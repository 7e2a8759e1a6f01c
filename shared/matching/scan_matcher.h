#ifndef FLEETMAP_SHARED_MATCHING_SCAN_MATCHER_H_
#define FLEETMAP_SHARED_MATCHING_SCAN_MATCHER_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"
#include "shared/matching/correlative_search.h"
#include "shared/matching/match_grid.h"
#include "shared/matching/match_grid_pyramid.h"
#include "shared/matching/pose_refinement.h"

namespace fleetmap {

struct ScanMatcherOptions {
  // Run the correlative search before refining (to escape bad guesses); otherwise refine only.
  bool use_correlative_search = true;
  CorrelativeSearchOptions search;
  PoseRefinementOptions refinement;
  // Matches whose refined mean score falls below this are reported as failures.
  double min_score = 0.3;
};

struct ScanMatchResult {
  Rigid2d pose;  // robot (points' frame) in the map
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d scan_information = Eigen::Matrix3d::Zero();
  double score = 0.0;  // refined mean per-point score, 0..1
  double inlier_fraction = 0.0;
  double search_score = 0.0;  // the correlative search's score (0 when it did not run)
};

// Matches scan points (robot frame) against `grid`: correlative search around `initial_guess`
// (branch and bound when `pyramid` is given, brute force on the grid otherwise), then
// refinement with `prior` as the pose prior. Empty when the grid or the scan is empty or the
// match is too poor.
std::optional<ScanMatchResult> MatchScan(const std::vector<Eigen::Vector2f>& points,
                                         const MatchGrid& grid, const MatchGridPyramid* pyramid,
                                         const Rigid2d& initial_guess, const Rigid2d& prior,
                                         const ScanMatcherOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_SCAN_MATCHER_H_
