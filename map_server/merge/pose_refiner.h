#ifndef FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_
#define FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/likelihood_field.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct PoseRefinerOptions {
  int max_iterations = 30;
  double huber_delta = 0.05;  // metres: points farther than this from a wall count less
  // Points farther than this from any target wall are treated as unmatched (no pull).
  double inlier_distance = 0.1;
  // The refinement must stay near the lattice answer it starts from; farther means it slid.
  double max_translation_change = 0.3;
  double max_rotation_change = 0.05;
};

struct RefinedPose {
  Rigid2d pose;
  double inlier_fraction = 0.0;     // points within inlier_distance of a target wall
  double mean_inlier_distance = 0.0;  // metres, the residual of the alignment
  bool converged = false;
};

// Sub-cell refinement of a correlative match: Gauss-Newton (Levenberg-Marquardt damped) on the
// point-to-nearest-wall distances of the source points in the target's distance field, with
// Huber weights. The branch-and-bound lattice gets within a cell; this gets within centimetres.
RefinedPose RefinePose(const LikelihoodField& target_field,
                       const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& initial,
                       const PoseRefinerOptions& options = PoseRefinerOptions());

// Inlier statistics of `pose` without moving it.
RefinedPose EvaluatePose(const LikelihoodField& target_field,
                         const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose,
                         double inlier_distance);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_MERGE_POSE_REFINER_H_
