#ifndef FLEETMAP_MAP_SERVER_MERGE_WHOLE_MAP_WALLS_H_
#define FLEETMAP_MAP_SERVER_MERGE_WHOLE_MAP_WALLS_H_

#include <Eigen/Core>
#include <vector>

#include "map_server/merge/match_target.h"
#include "map_server/merge/trail_walls.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

// How walls seen through are counted (MatchTarget::LocallyFittedContradictionsAt). The merge
// engine sets these from MergeEngineOptions::whole_map_contradiction_*; the defaults are its.
struct WallCountOptions {
  double tile = 8.0;               // metres
  double window = 0.4;             // metres, when fitted
  double window_per_metre = 0.01;  // when fitted
};

// Two parts' whole maps, a and b, at one resolution, ready to match b on a and to count the
// walls of either that an alignment puts in space the other saw free. Bodies mapped where
// robots drove are not walls seen through (trail_walls.h): a blob of one map is excused when
// it lies wholly on its own part's trails, or on the other part's once aligned.
class WholeMapWalls {
 public:
  // `trails_a` and `trails_b`: where each part's robots drove, in its own map's frame.
  WholeMapWalls(const OccupancyGrid& map_a, const OccupancyGrid& map_b,
                const MatchTargetOptions& match_options, TrailMask trails_a, TrailMask trails_b,
                const WallCountOptions& count_options);
  WholeMapWalls(const WholeMapWalls&) = delete;
  WholeMapWalls& operator=(const WholeMapWalls&) = delete;

  bool empty() const { return target_a_.empty() || points_b_.coarse.empty(); }
  const MatchTarget& target_a() const { return target_a_; }
  const MatchTarget& target_b() const { return target_b_; }
  const MatchSource& points_a() const { return points_a_; }  // a's walls, a's frame
  const MatchSource& points_b() const { return points_b_; }  // b's walls, b's frame
  // b's walls moved so that their centroid is the origin: turned about it, b's map stays over
  // the same part of a, so a search window only has to cover a. Alignments of the centred map
  // are what Contradictions() takes.
  const MatchSource& centred_b() const { return centred_b_; }
  const Eigen::Vector2d& centroid_b() const { return centroid_b_; }
  // The whole map b in a's frame, from an alignment of the centred one, and back.
  Rigid2d Whole(const Rigid2d& centred_b_in_a) const;
  Rigid2d Centred(const Rigid2d& b_in_a) const;

  // Each map's walls but for bodies on its own part's trails (a symmetry of one map moves it
  // onto itself; the other part's trails play no part).
  std::vector<Eigen::Vector2d> WallsOffOwnTrailsA() const;
  std::vector<Eigen::Vector2d> WallsOffOwnTrailsB() const;

  // The walls of either map that `centred_b_in_a` puts in space the other saw free, but for
  // bodies on trails; with each tile of a map fitted on its own first when `fitted`.
  int Contradictions(const Rigid2d& centred_b_in_a, bool fitted) const;
  // The same, fitted, counting the bodies on trails too.
  int ContradictionsWithTrails(const Rigid2d& centred_b_in_a) const;

 private:
  int Crossings(const MatchTarget& map, const std::vector<Eigen::Vector2d>& walls,
                const Rigid2d& pose, bool fitted) const;

  MatchTarget target_a_;
  MatchTarget target_b_;
  MatchSource points_a_;
  MatchSource points_b_;
  MatchSource centred_b_;
  Eigen::Vector2d centroid_b_;
  WallBlobs blobs_a_;
  WallBlobs blobs_b_;
  std::vector<int> blob_of_a_;  // per fine point of a, its blob
  std::vector<int> blob_of_b_;
  TrailMask trails_a_;
  TrailMask trails_b_;
  std::vector<bool> own_a_;  // per blob of a, whether wholly on a's trails
  std::vector<bool> own_b_;
  WallCountOptions count_options_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_WHOLE_MAP_WALLS_H_
