#include "shared/matching/scan_matcher.h"

namespace fleetmap {

std::optional<ScanMatchResult> MatchScan(const std::vector<Eigen::Vector2f>& points,
                                         const MatchGrid& grid, const MatchGridPyramid* pyramid,
                                         const Rigid2d& initial_guess, const Rigid2d& prior,
                                         const ScanMatcherOptions& options) {
  if (points.empty() || grid.empty() || !initial_guess.IsFinite() || !prior.IsFinite()) {
    return std::nullopt;
  }
  Rigid2d start = initial_guess;
  double search_score = 0.0;
  if (options.use_correlative_search) {
    const std::optional<CorrelativeMatch> coarse =
        pyramid != nullptr ? SearchBranchAndBound(points, *pyramid, initial_guess, options.search)
                           : SearchBruteForce(points, grid, initial_guess, options.search);
    if (!coarse) return std::nullopt;
    start = coarse->pose;
    search_score = coarse->score;
  }
  const PoseRefinement refined = RefinePose(points, grid, start, prior, options.refinement);
  if (refined.score < options.min_score || !refined.pose.IsFinite()) return std::nullopt;
  ScanMatchResult result;
  result.pose = refined.pose;
  result.covariance = refined.covariance;
  result.scan_information = refined.scan_information;
  result.score = refined.score;
  result.inlier_fraction = refined.inlier_fraction;
  result.search_score = search_score;
  return result;
}

}  // namespace fleetmap
