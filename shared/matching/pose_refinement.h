#ifndef FLEETMAP_SHARED_MATCHING_POSE_REFINEMENT_H_
#define FLEETMAP_SHARED_MATCHING_POSE_REFINEMENT_H_

#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"

namespace fleetmap {

struct PoseRefinementOptions {
  int max_iterations = 20;
  // Standard deviation of one point's distance to the map (metres): scales the scan's
  // information against the prior's.
  double point_sigma = 0.05;
  // Cauchy loss scale (metres): points farther than this from the map count progressively less.
  double robust_scale = 0.15;
  // Then refined again from that pose with this narrower scale (0: not). The wide scale gives the
  // basin that odometry errors of several centimetres need; at the minimum it lets the few
  // returns off surfaces the map has not seen yet (a box face coming into view, an occlusion
  // edge) pull the pose with a sizeable share of their weight.
  double fine_robust_scale = 0.0;
  // Prior on the pose (typically odometry): keeps directions the scan cannot observe, such as the
  // axis of a featureless corridor, where the prior puts them. A sigma <= 0 disables that term.
  double prior_translation_sigma = 0.3;  // metres, per axis
  double prior_rotation_sigma = 0.2;     // radians
  // A point closer to the map than this counts as an inlier in the quality figures.
  double inlier_distance = 0.1;
};

struct PoseRefinement {
  Rigid2d pose;  // robot (points' frame) in the map
  // Inverse of the Gauss-Newton information (scan + prior) at the solution, over (x, y, theta)
  // in the map frame. It treats points as independent, so it is optimistic in absolute terms but
  // its shape (which direction is unconstrained) is right.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  // The scan's own information, without the prior: its smallest eigenvalue tells whether the
  // geometry constrains all three directions.
  Eigen::Matrix3d scan_information = Eigen::Matrix3d::Zero();
  double score = 0.0;            // mean per-point score, 0..1 (see SquaredDistanceScore)
  double inlier_fraction = 0.0;  // share of points within inlier_distance of the map
  int iterations = 0;
  bool converged = false;
};

// Levenberg-Marquardt on the interpolated squared-distance field: minimises the robustified
// squared distances of the transformed points plus the prior term, starting at `initial`.
PoseRefinement RefinePose(const std::vector<Eigen::Vector2f>& points, const MatchGrid& grid,
                          const Rigid2d& initial, const Rigid2d& prior,
                          const PoseRefinementOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_POSE_REFINEMENT_H_
