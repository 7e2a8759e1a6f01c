#include "map_server/merge/match_target.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <utility>

#include "map_server/merge/grid_points.h"

namespace fleetmap {

namespace {

void Keep(const std::vector<size_t>& indices, std::vector<Eigen::Vector2d>* values) {
  std::vector<Eigen::Vector2d> kept;
  kept.reserve(indices.size());
  for (size_t i : indices) kept.push_back((*values)[i]);
  *values = std::move(kept);
}

}  // namespace

MatchSource MakeMatchSource(const OccupancyGrid& grid, const Rigid2d& grid_to_source,
                            const MatchTargetOptions& options) {
  MatchSource source;
  source.fine = OccupiedPoints(grid, options.grid.occupied_log_odds, grid_to_source);
  source.fine_normals =
      WallNormals(grid, options.grid.occupied_log_odds, options.grid.free_log_odds, grid_to_source);
  source.coarse = source.fine;
  source.coarse_normals = source.fine_normals;
  ThinSource(grid.resolution() * 0.99, options, &source);
  return source;
}

void TransformSource(const Rigid2d& t, MatchSource* source) {
  const Eigen::Matrix2d r = t.rotation_matrix();
  for (Eigen::Vector2d& p : source->coarse) p = t * p;
  for (Eigen::Vector2d& p : source->fine) p = t * p;
  for (Eigen::Vector2d& n : source->coarse_normals) n = r * n;
  for (Eigen::Vector2d& n : source->fine_normals) n = r * n;
}

void AppendSource(const MatchSource& part, MatchSource* source) {
  const auto append = [](const std::vector<Eigen::Vector2d>& from, std::vector<Eigen::Vector2d>* to) {
    to->insert(to->end(), from.begin(), from.end());
  };
  append(part.coarse, &source->coarse);
  append(part.fine, &source->fine);
  append(part.coarse_normals, &source->coarse_normals);
  append(part.fine_normals, &source->fine_normals);
}

void KeepPointsSeenBy(const OccupancyGrid& grid, const Rigid2d& source_to_grid,
                      MatchSource* source) {
  const auto seen = [&](const std::vector<Eigen::Vector2d>& points) {
    std::vector<size_t> indices;
    for (size_t i = 0; i < points.size(); ++i) {
      const CellIndex cell = grid.CellAt(source_to_grid * points[i]);
      if (grid.Contains(cell) && grid.IsKnown(cell)) indices.push_back(i);
    }
    return indices;
  };
  const std::vector<size_t> coarse = seen(source->coarse);
  Keep(coarse, &source->coarse);
  Keep(coarse, &source->coarse_normals);
  const std::vector<size_t> fine = seen(source->fine);
  Keep(fine, &source->fine);
  Keep(fine, &source->fine_normals);
}

void ThinSource(double fine_voxel, const MatchTargetOptions& options, MatchSource* source) {
  const std::vector<size_t> coarse =
      VoxelFilterIndices(source->coarse, options.source_voxel, options.max_source_points);
  Keep(coarse, &source->coarse);
  Keep(coarse, &source->coarse_normals);
  const std::vector<size_t> fine = VoxelFilterIndices(source->fine, fine_voxel, options.max_fine_points);
  Keep(fine, &source->fine);
  Keep(fine, &source->fine_normals);
}

MatchTarget::MatchTarget(const OccupancyGrid& target, const MatchTargetOptions& options)
    : options_(options), grid_(target, options.grid), target_(target) {
  matcher_ = std::make_unique<BranchAndBoundMatcher>(grid_, options.search);
  LikelihoodFieldOptions field_options;
  field_options.occupied_probability = LogOddsToProbability(options.grid.occupied_log_odds);
  field_options.max_distance = options.fine_field_max_distance;
  fine_field_ = std::make_shared<const LikelihoodField>(target, field_options);
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

MatchGates WithoutMinimums(MatchGates gates) {
  gates.min_score = 0.0;
  gates.min_points = 0;
  return gates;
}

SearchWindow MatchTarget::Everywhere() const {
  SearchWindow window;
  window.center = Rigid2d(0.5 * (min_corner() + max_corner()), 0.0);
  window.linear_half_extent = 0.5 * (max_corner() - min_corner());
  window.angular_half_extent = M_PI;
  return window;
}

Rigid2d MatchTarget::BestFitNear(const MatchSource& source, const Rigid2d& pose,
                                 const MatchGates& gates) const {
  SearchWindow near;
  near.center = pose;
  near.linear_half_extent = Eigen::Vector2d::Constant(grid_.resolution());
  near.angular_half_extent = 0.01;
  const MatchResult fit = Match(source, near, WithoutMinimums(gates));
  return fit.found ? fit.pose : pose;
}

MatchResult MatchTarget::Evaluate(const MatchSource& source, const Rigid2d& pose,
                                  const MatchGates& gates) const {
  return EvaluateWithScore(source, pose, gates, matcher_->ScoreAt(source.coarse, pose));
}

int MatchTarget::ContradictionsAt(const std::vector<Eigen::Vector2d>& points,
                                  const Rigid2d& pose) const {
  int count = 0;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d c = grid_.ToCellCoordinates(pose * p);
    const int x = static_cast<int>(std::floor(c.x())), y = static_cast<int>(std::floor(c.y()));
    // Known cells score above zero within twice sigma of a wall; beyond, only seen-free remains.
    count += grid_.Known(x, y) && grid_.Value(x, y) <= 0.0f;
  }
  return count;
}

int MatchTarget::LocallyFittedContradictionsAt(const std::vector<Eigen::Vector2d>& points,
                                               const Rigid2d& pose, double tile, double window,
                                               double window_per_metre) const {
  if (!(window > 0.0) || !(tile > 0.0) || points.empty()) return ContradictionsAt(points, pose);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) centroid += p;
  centroid /= static_cast<double>(points.size());
  std::map<std::pair<int, int>, std::vector<Eigen::Vector2d>> tiles;
  for (const Eigen::Vector2d& p : points) {
    tiles[{static_cast<int>(std::floor(p.x() / tile)), static_cast<int>(std::floor(p.y() / tile))}]
        .push_back(p);
  }
  int count = 0;
  for (const auto& [key, tile_points] : tiles) {
    const Eigen::Vector2d centre = (Eigen::Vector2d(key.first, key.second).array() + 0.5) * tile;
    const double reach = std::min(window, window_per_metre * (centre - centroid).norm());
    const int steps = static_cast<int>(std::floor(reach / grid_.resolution() + 1e-9));
    std::vector<Eigen::Vector2d> placed;
    placed.reserve(tile_points.size());
    for (const Eigen::Vector2d& p : tile_points) placed.push_back(pose * p);
    int least = ContradictionsAt(placed, Rigid2d());
    for (int dx = -steps; dx <= steps && least > 0; ++dx) {
      for (int dy = -steps; dy <= steps && least > 0; ++dy) {
        const Rigid2d shift(Eigen::Vector2d(dx, dy) * grid_.resolution(), 0.0);
        least = std::min(least, ContradictionsAt(placed, shift));
      }
    }
    count += least;
  }
  return count;
}

PeakSearch MatchTarget::PeaksOutside(const MatchSource& source, const SearchWindow& window,
                                     double min_score,
                                     const std::vector<ExclusionZone>& zones) const {
  static const std::vector<Eigen::Vector2d> kNothing;
  return matcher_->Peaks(empty() ? kNothing : source.coarse, window, min_score, zones);
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
  const auto second =
      matcher_->Search(source.coarse, window, gates.max_ambiguity * best->score, {zone});
  // Sided distances only where the source can land during the refinement (plus the field's
  // reach): building them over a whole map for every match would cost more than the search.
  Box2d box{best->pose.translation(), best->pose.translation()};
  for (const Eigen::Vector2d& p : source.fine) {
    box.min = box.min.cwiseMin(best->pose * p);
    box.max = box.max.cwiseMax(best->pose * p);
  }
  const double reach = options_.refine.sided_search_translation +
                       options_.refine.max_translation_change + options_.fine_field_max_distance;
  box.min.array() -= reach;
  box.max.array() += reach;
  const SidedDistanceField sided(target_, box, options_.grid.occupied_log_odds,
                                 options_.grid.free_log_odds, fine_field_);
  const Box2d allowed{window.center.translation() - window.linear_half_extent,
                      window.center.translation() + window.linear_half_extent};
  const RefinedPose refined =
      RefineSidedPose(sided, {source.coarse, source.coarse_normals},
                      {source.fine, source.fine_normals}, best->pose, allowed, options_.refine);
  // The lattice score is the search's verdict: the side-blind score grid may rate the refined
  // pose (a wall thickness off the lattice answer, faces on their own faces) lower.
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
