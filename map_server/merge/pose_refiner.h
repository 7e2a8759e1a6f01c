#ifndef FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_
#define FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_

#include <Eigen/Core>
#include <vector>

#include "map_server/merge/sided_distance_field.h"
#include "shared/core/likelihood_field.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct PoseRefinerOptions {
  int max_iterations = 30;
  double huber_delta = 0.05;  // metres: points farther than this from a wall count less
  // Metres: points farther than this from a wall do not pull at all. Huber's pull never fades,
  // and without detections another robot's body, mapped where the two passed each other, pulled
  // every match of those submaps: robot2 of east_end was placed 0.74 deg off, 0.16 with this
  // (docs/BENCHMARKS.md, issue 8, session 23). 0: only the distance field's reach limits them.
  double max_pull_distance = 0.15;
  // A point closer than this to a target wall is an inlier (the match's quality figures).
  double inlier_distance = 0.1;
  // The refinement must stay near the lattice answer it starts from; farther means it slid.
  double max_translation_change = 0.3;
  double max_rotation_change = 0.05;
  // The lattice answer's neighbourhood searched again on sided distances (RefineSidedPose),
  // each pose scored by exp(-d^2 / 2 sigma^2) over the coarse points' sided distances.
  double sided_search_translation = 0.2;  // metres, +-: interior walls are 0.1-0.2 m thick
  double sided_search_rotation = 0.03;    // radians, +-
  double sided_search_sigma = 0.05;       // metres
  double sided_search_prior = 1.0;  // metres: sigma of a weak prior towards the lattice answer
};

struct RefinedPose {
  Rigid2d pose;
  double inlier_fraction = 0.0;       // points within inlier_distance of a target wall
  double mean_inlier_distance = 0.0;  // metres, the residual of the alignment
  bool converged = false;
};

// A source map's wall points with the side each was seen from (zero: none), in its frame.
struct SidedPoints {
  const std::vector<Eigen::Vector2d>& points;
  const std::vector<Eigen::Vector2d>& normals;
};

// Sub-cell refinement of a correlative match: Gauss-Newton (Levenberg-Marquardt damped) on the
// distances of the `fine` source points to the target's walls seen from the same side (see
// SidedDistanceField; a point without a side finds any wall), with Huber weights, and none
// beyond max_pull_distance. The
// branch-and-bound lattice gets within a cell, but it is blind to sides and may have put faces
// onto the opposite faces of the same walls, a wall thickness away: so the lattice answer's
// neighbourhood is first searched again on sided distances with the `coarse` points
// (PoseRefinerOptions::sided_search_*; translations inside `allowed` only, the caller's search
// window). This gets within centimetres.
RefinedPose RefineSidedPose(const SidedDistanceField& target_field, const SidedPoints& coarse,
                            const SidedPoints& fine, const Rigid2d& initial, const Box2d& allowed,
                            const PoseRefinerOptions& options = PoseRefinerOptions());

// Inlier statistics of `pose` without moving it.
RefinedPose EvaluatePose(const LikelihoodField& target_field,
                         const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose,
                         double inlier_distance);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_
