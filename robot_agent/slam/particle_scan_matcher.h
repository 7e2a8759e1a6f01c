#ifndef FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SCAN_MATCHER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SCAN_MATCHER_H_

#include <vector>

#include <Eigen/Core>

#include "robot_agent/slam/shared_grid_tiles.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct ParticleMatcherOptions {
  // Correspondences are searched this many cells around each point: wide first (basin), then
  // narrow (accuracy).
  int coarse_radius = 4;
  int fine_radius = 2;
  int coarse_iterations = 4;
  int max_iterations = 15;
  // Stop when an iteration moves less than this (metres / radians).
  double min_step = 1e-4;
  // A match is good when at least this share of the points found a correspondence.
  double min_inlier_fraction = 0.5;
  int min_points = 20;
  // Observation model: per point, log N(d; 0, sigma) with d the distance to the nearest hit
  // point, clamped at `fine_radius` cells.
  double sigma = 0.05;
};

struct ParticleMatch {
  Rigid2d pose;
  double inlier_fraction = 0.0;
  bool good = false;
};

// Point-to-point ICP of scan points (robot frame) against a particle's map, from `initial`.
// Correspondences are the mean hit points of occupied cells, so the result is not quantised to
// the 5 cm grid.
ParticleMatch MatchAgainstTiles(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                                const Rigid2d& initial, const ParticleMatcherOptions& options);

// Share of `points` with a map hit within fine_radius cells at `pose`.
double InlierFraction(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                      const Rigid2d& pose, const ParticleMatcherOptions& options);
// Whether a match at `pose` would pass MatchAgainstTiles' gate (min_points, min_inlier_fraction).
bool GoodMatchAt(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                 const Rigid2d& pose, const ParticleMatcherOptions& options);

// Log-likelihood of the points at `pose` in the map (up to a constant).
double ScanLogLikelihood(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& grid,
                         const Rigid2d& pose, const ParticleMatcherOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_PARTICLE_SCAN_MATCHER_H_
