#include "map_server/merge/whole_map_walls.h"

#include <utility>

#include "map_server/merge/grid_points.h"

namespace fleetmap {

namespace {

// The wall points of a map a robot's body does not explain: `blob_of[i]` is point i's blob,
// excused where `own` (the map's own robots' trails) or `other` (the other part's) says so.
std::vector<Eigen::Vector2d> WallsOffTrails(const std::vector<Eigen::Vector2d>& points,
                                            const std::vector<int>& blob_of,
                                            const std::vector<bool>& own,
                                            const std::vector<bool>& other) {
  std::vector<Eigen::Vector2d> kept;
  kept.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const int blob = blob_of[i];
    if (blob >= 0 && (own[blob] || other[blob])) continue;
    kept.push_back(points[i]);
  }
  return kept;
}

std::vector<int> BlobsOf(const WallBlobs& blobs, const std::vector<Eigen::Vector2d>& points) {
  std::vector<int> blob_of;
  blob_of.reserve(points.size());
  for (const Eigen::Vector2d& p : points) blob_of.push_back(blobs.BlobAt(p));
  return blob_of;
}

}  // namespace

WholeMapWalls::WholeMapWalls(const OccupancyGrid& map_a, const OccupancyGrid& map_b,
                             const MatchTargetOptions& match_options, TrailMask trails_a,
                             TrailMask trails_b, const WallCountOptions& count_options)
    : target_a_(map_a, match_options),
      target_b_(map_b, match_options),
      points_a_(MakeMatchSource(map_a, Rigid2d(), match_options)),
      points_b_(MakeMatchSource(map_b, Rigid2d(), match_options)),
      centred_b_(points_b_),
      centroid_b_(Centroid(points_b_.coarse)),
      blobs_a_(map_a, match_options.grid.occupied_log_odds),
      blobs_b_(map_b, match_options.grid.occupied_log_odds),
      blob_of_a_(BlobsOf(blobs_a_, points_a_.fine)),
      blob_of_b_(BlobsOf(blobs_b_, points_b_.fine)),
      trails_a_(std::move(trails_a)),
      trails_b_(std::move(trails_b)),
      own_a_(blobs_a_.OnTrails(trails_a_, Rigid2d())),
      own_b_(blobs_b_.OnTrails(trails_b_, Rigid2d())),
      count_options_(count_options) {
  TransformSource(Rigid2d(-centroid_b_, 0.0), &centred_b_);
}

Rigid2d WholeMapWalls::Whole(const Rigid2d& centred_b_in_a) const {
  return centred_b_in_a * Rigid2d(-centroid_b_, 0.0);
}

Rigid2d WholeMapWalls::Centred(const Rigid2d& b_in_a) const {
  return b_in_a * Rigid2d(centroid_b_, 0.0);
}

std::vector<Eigen::Vector2d> WholeMapWalls::WallsOffOwnTrailsA() const {
  return WallsOffTrails(points_a_.fine, blob_of_a_, own_a_, own_a_);
}

std::vector<Eigen::Vector2d> WholeMapWalls::WallsOffOwnTrailsB() const {
  return WallsOffTrails(points_b_.fine, blob_of_b_, own_b_, own_b_);
}

int WholeMapWalls::Crossings(const MatchTarget& map, const std::vector<Eigen::Vector2d>& walls,
                             const Rigid2d& pose, bool fitted) const {
  return map.LocallyFittedContradictionsAt(walls, pose, count_options_.tile,
                                           fitted ? count_options_.window : 0.0,
                                           count_options_.window_per_metre);
}

int WholeMapWalls::Contradictions(const Rigid2d& centred_b_in_a, bool fitted) const {
  const Rigid2d b_in_a = Whole(centred_b_in_a);
  const std::vector<Eigen::Vector2d> walls_b =
      WallsOffTrails(centred_b_.fine, blob_of_b_, own_b_, blobs_b_.OnTrails(trails_a_, b_in_a));
  const std::vector<Eigen::Vector2d> walls_a = WallsOffTrails(
      points_a_.fine, blob_of_a_, own_a_, blobs_a_.OnTrails(trails_b_, b_in_a.inverse()));
  return Crossings(target_a_, walls_b, centred_b_in_a, fitted) +
         Crossings(target_b_, walls_a, b_in_a.inverse(), fitted);
}

int WholeMapWalls::ContradictionsWithTrails(const Rigid2d& centred_b_in_a) const {
  return Crossings(target_a_, centred_b_.fine, centred_b_in_a, true) +
         Crossings(target_b_, points_a_.fine, Whole(centred_b_in_a).inverse(), true);
}

}  // namespace fleetmap
