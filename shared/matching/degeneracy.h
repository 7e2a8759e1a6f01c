#ifndef FLEETMAP_SHARED_MATCHING_DEGENERACY_H_
#define FLEETMAP_SHARED_MATCHING_DEGENERACY_H_

#include <Eigen/Core>
#include <vector>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// Mean of n n^T over the surface normals of a scan (robot frame), each normal taken from the
// point's neighbours in beam order when they are closer than `max_gap` (metres). Its eigenvalues
// say how much of the scan faces each direction: in a plain corridor the one along the axis is
// ~0. Unlike the matcher's information matrix it does not see the ripples a distance field built
// from sampled wall points has along the wall, which can trap a match at its previous position.
Eigen::Matrix2d NormalScatter(const std::vector<Eigen::Vector2f>& points_in_beam_order,
                              double max_gap = 0.2);

// Keeps `matched`'s translation along the directions the scan observes (scatter eigenvalue at
// least `min_eigenvalue`) and `predicted`'s (odometry) along the others; rotation from `matched`.
Rigid2d KeepObservedDirections(const Rigid2d& predicted, const Rigid2d& matched,
                               const Eigen::Matrix2d& scatter_in_robot, double min_eigenvalue);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_DEGENERACY_H_
