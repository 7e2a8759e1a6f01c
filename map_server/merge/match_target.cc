#include "map_server/merge/match_target.h"

#include <cmath>
#include <sstream>

#include "map_server/merge/grid_points.h"

namespace fleetmap {

MatchSource MakeMatchSource(const OccupancyGrid& grid, const Rigid2d& grid_to_source,
                            const MatchTargetOptions& options) {
  const std::vector<Eigen::Vector2d> all =
      OccupiedPoints(grid, options.grid.occupied_log_odds, grid_to_source);
  MatchSource source;
  source.coarse = VoxelFilter(all, options.source_voxel, options.max_source_points);
  source.fine = VoxelFilter(all, grid.resolution() * 0.99, options.max_fine_points);
  return source;
}

MatchTarget::MatchTarget(const OccupancyGrid& target, const MatchTargetOptions& options)
    : options_(options), grid_(target, options.grid) {
  matcher_ = std::make_unique<BranchAndBoundMatcher>(grid_, options.search);
  LikelihoodFieldOptions field_options;
  field_options.occupied_probability = LogOddsToProbability(options.grid.occupied_log_odds);
  field_options.max_distance = options.fine_field_max_distance;
  fine_field_ = std::make_unique<LikelihoodField>(target, field_options);
}

namespace {

std::string Describe(const MatchResult& r) {
  std::ostringstream os;
  os.precision(3);
  os << "score " << r.score << ", ambiguity " << r.ambiguity << ", overlap " << r.overlap
     << ", inliers " << r.inlier_fraction << ", residual " << r.residual << " m, on the overlap: score "
     << r.overlap_score << ", inliers " << r.overlap_inlier_fraction;
  return os.str();
}

bool KnownAt(const ScoreGrid& grid, const Eigen::Vector2d& point) {
  const Eigen::Vector2d c = grid.ToCellCoordinates(point);
  return grid.Known(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
}

// Mean score of the points landing on observed cells.
double OverlapScore(const ScoreGrid& grid, const std::vector<Eigen::Vector2d>& points, const Rigid2d& pose) {
  double sum = 0.0;
  int known = 0;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d c = grid.ToCellCoordinates(pose * p);
    const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
    if (!grid.Known(x, y)) continue;
    ++known;
    sum += grid.Value(x, y);
  }
  return known > 0 ? sum / known : 0.0;
}

// Fraction of the points landing on observed cells that lie within `inlier_distance` of a wall.
double OverlapInlierFraction(const ScoreGrid& grid, const LikelihoodField& field,
                             const std::vector<Eigen::Vector2d>& points, const Rigid2d& pose,
                             double inlier_distance) {
  int known = 0, inliers = 0;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = pose * p;
    if (!KnownAt(grid, q)) continue;
    ++known;
    inliers += field.Distance(q) < inlier_distance;
  }
  return known > 0 ? static_cast<double>(inliers) / known : 0.0;
}

}  // namespace

MatchResult MatchTarget::Evaluate(const MatchSource& source, const Rigid2d& pose,
                                  const MatchGates& gates) const {
  return EvaluateWithScore(source, pose, gates, matcher_->ScoreAt(source.coarse, pose));
}

std::optional<MatchCandidate> MatchTarget::BestOutside(const MatchSource& source,
                                                       const SearchWindow& window,
                                                       double min_score,
                                                       const ExclusionZone& zone) const {
  if (empty() || source.coarse.empty()) return std::nullopt;
  return matcher_->Search(source.coarse, window, min_score, zone);
}

MatchResult MatchTarget::EvaluateWithScore(const MatchSource& source, const Rigid2d& pose,
                                           const MatchGates& gates, double score) const {
  MatchResult result;
  result.pose = pose;
  result.score = score;
  result.overlap = matcher_->OverlapAt(source.coarse, pose);
  const RefinedPose fine =
      EvaluatePose(*fine_field_, source.fine, pose, options_.refine.inlier_distance);
  result.inlier_fraction = fine.inlier_fraction;
  result.residual = fine.mean_inlier_distance;
  result.overlap_score = OverlapScore(grid_, source.coarse, pose);
  result.overlap_inlier_fraction = OverlapInlierFraction(grid_, *fine_field_, source.fine, pose,
                                                         options_.refine.inlier_distance);
  const double judged_score = gates.judge_overlap_only ? result.overlap_score : result.score;
  const double judged_inliers =
      gates.judge_overlap_only ? result.overlap_inlier_fraction : result.inlier_fraction;
  result.found = judged_score >= gates.min_score;
  if (static_cast<int>(source.coarse.size()) < gates.min_points) {
    result.reason = "too few wall points in the source";
  } else if (!result.found) {
    result.reason = "score below gate";
  } else if (result.overlap < gates.min_overlap) {
    result.reason = "overlap below gate";
  } else if (judged_inliers < gates.min_inlier_fraction) {
    result.reason = "inlier fraction below gate";
  } else {
    result.accepted = true;
  }
  result.reason = (result.accepted ? "" : result.reason + ": ") + Describe(result);
  return result;
}

MatchResult MatchTarget::Match(const MatchSource& source, const SearchWindow& window,
                               const MatchGates& gates) const {
  MatchResult result;
  if (static_cast<int>(source.coarse.size()) < gates.min_points) {
    result.reason = "too few wall points in the source (" + std::to_string(source.coarse.size()) + ")";
    return result;
  }
  if (empty()) {
    result.reason = "empty target map";
    return result;
  }
  // Unknown target cells score >= 0, so a pose whose overlap passes both gates scores at
  // least min_score * min_overlap over all points.
  const double floor = gates.judge_overlap_only ? gates.min_score * gates.min_overlap : gates.min_score;
  const auto best = matcher_->Search(source.coarse, window, floor);
  if (!best) {
    result.reason = "no pose scores above " + std::to_string(floor);
    return result;
  }
  ExclusionZone zone = gates.distinct;
  zone.center = best->pose;
  const auto second = matcher_->Search(source.coarse, window, gates.max_ambiguity * best->score, zone);
  const RefinedPose refined = RefinePose(*fine_field_, source.fine, best->pose, options_.refine);
  // The lattice score is the search's verdict; the refined pose only moves within a cell.
  result = EvaluateWithScore(source, refined.pose, gates,
                             std::max(best->score, matcher_->ScoreAt(source.coarse, refined.pose)));
  if (second) {
    result.second_score = second->score;
    result.ambiguity = second->score / best->score;
    result.accepted = false;
    std::ostringstream os;
    os << "ambiguous: a distinct pose " << second->pose << " scores " << second->score
       << " vs " << best->score << " at " << best->pose;
    result.reason = os.str();
  } else if (result.accepted) {
    result.reason = Describe(result);
  }
  return result;
}

}  // namespace fleetmap
