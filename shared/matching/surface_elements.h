#ifndef FLEETMAP_SHARED_MATCHING_SURFACE_ELEMENTS_H_
#define FLEETMAP_SHARED_MATCHING_SURFACE_ELEMENTS_H_

#include <vector>

#include <Eigen/Core>

namespace fleetmap {

struct SurfaceFitOptions {
  // Neighbours within this radius (metres) decide whether a point lies on a straight wall.
  // 0 turns the fit off: every point stays a point.
  double radius = 0.2;
  // A neighbourhood is a line when its spread across the line is at most this share of its
  // spread along it (ratio of standard deviations).
  double max_flatness = 0.25;
  // Fewer points than this in the neighbourhood (the point included) cannot show a line.
  int min_points = 3;
  // How far an element may reach along its wall (metres). It reaches at least halfway to its
  // nearest neighbour on each side, so that the elements of a sparsely sampled wall meet.
  double max_extent = 0.1;
};

// A short piece of wall a point stands for: the segment from centre - extent_minus * tangent to
// centre + extent_plus * tangent. A point whose neighbourhood is not a line (a corner, a pole,
// an isolated return) has a zero tangent and zero extents: it stays a point.
struct SurfaceElement {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d tangent = Eigen::Vector2d::Zero();
  double extent_minus = 0.0;
  double extent_plus = 0.0;
};

// One element per input point, in input order. Why: a distance field built from sampled wall
// points has a ripple along the wall (between two samples s apart the squared distance rises
// by (s/2)^2), and a new scan that hits the same spots as the last one sits in that ripple's
// minimum instead of moving with the robot. Distances to the fitted wall have no such ripple.
// `min_extent` is how far an element reaches towards a neighbour that is closer than that (the
// map keeps one element per cell, so it is the cell size). Points are taken as they are: the
// caller drops non-finite ones.
std::vector<SurfaceElement> FitSurfaceElements(const std::vector<Eigen::Vector2d>& points,
                                               double min_extent, const SurfaceFitOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_SURFACE_ELEMENTS_H_
