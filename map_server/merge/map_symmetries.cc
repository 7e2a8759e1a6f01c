#include "map_server/merge/map_symmetries.h"

#include <algorithm>

#include "map_server/merge/grid_points.h"

namespace fleetmap {

std::vector<Rigid2d> MapSymmetries(const MatchTarget& target, const MatchSource& source,
                                   const std::vector<Eigen::Vector2d>& walls,
                                   const MapSymmetryOptions& options) {
  std::vector<Rigid2d> found;
  if (target.empty() || source.coarse.empty() || options.max_examined <= 0) return found;
  // Turned about the map's centroid, so that the window only has to cover the map.
  const Eigen::Vector2d c = Centroid(source.coarse);
  MatchSource centred = source;
  TransformSource(Rigid2d(-c, 0.0), &centred);
  const Rigid2d identity(c, 0.0);  // the centred map back where it was
  const MatchGates any = WithoutMinimums(options.gates);
  const MatchResult at_identity = target.Evaluate(centred, identity, any);
  if (!(at_identity.overlap_score > 0.0)) return found;
  const SearchWindow window = target.Everywhere();
  ExclusionZone zone = options.distinct;
  zone.center = identity;
  // A move scores over all points at least its overlap times its score there.
  PeakSearch peaks = target.PeaksOutside(
      centred, window, options.min_overlap * options.min_overlap_score * at_identity.overlap_score,
      {zone});
  for (int examined = 0; examined < options.max_examined; ++examined) {
    const auto peak = peaks.Next();
    if (!peak) break;
    zone.center = peak->pose;
    peaks.Exclude(zone);
    const Rigid2d pose = target.BestFitNear(centred, peak->pose, options.gates);
    const MatchResult at_pose = target.Evaluate(centred, pose, any);
    if (at_pose.overlap < options.min_overlap ||
        at_pose.overlap_score < options.min_overlap_score * at_identity.overlap_score) {
      continue;
    }
    const Rigid2d move = pose * Rigid2d(-c, 0.0);
    // Refined back onto no move, or onto a move already found: not distinct.
    const auto close_to = [&](const Rigid2d& other) {
      ExclusionZone around = options.distinct;
      around.center = other;
      return around.Contains(move);
    };
    if (close_to(Rigid2d()) || std::any_of(found.begin(), found.end(), close_to)) continue;
    if (target.ContradictionsAt(walls, move) >= options.max_contradictions) continue;
    found.push_back(move);
  }
  return found;
}

}  // namespace fleetmap
