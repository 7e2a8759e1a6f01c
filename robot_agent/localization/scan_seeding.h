#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_SCAN_SEEDING_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_SCAN_SEEDING_H_

#include <memory>
#include <optional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/localization/particle.h"
#include "shared/core/occupancy_grid.h"
#include "shared/matching/correlative_search.h"
#include "shared/matching/match_grid.h"
#include "shared/matching/match_grid_pyramid.h"

namespace fleetmap {

// Global localization by scan matching ("sensor resetting"): while a robot does not know where
// it is, its scan is matched against the whole map (branch and bound over every position and
// heading) and some particles are moved to the best match. A uniform belief rarely has a
// particle close enough to the truth for the likelihood field to prefer it over a look-alike
// place; the search puts some there. It stops once the filter agrees with it, or once another
// robot's detection has said where the robot is (the search cannot tell look-alike places
// apart: in a symmetric building it keeps choosing one twin).
struct ScanSeedingOptions {
  bool enabled = true;
  double interval = 1.0;      // seconds of sensor time between searches
  double fraction = 0.2;      // of the particles moved to the match
  double min_score = 0.5;     // mean per-point score of the match (0..1), below it nothing moves
  double position_std = 0.1;  // metres, spread of the moved particles
  double heading_std = 0.05;  // radians
  double resolution = 0.1;    // metres per cell of the search grid
  double max_range = 8.0;     // returns used, metres
  int max_points = 120;       // evenly taken from those returns
  // The search stops once this many matches in a row agreed with a converged estimate (within
  // agreement_distance metres and agreement_angle radians).
  int agreements_to_stop = 3;
  double agreement_distance = 0.5;
  double agreement_angle = 0.2;
};

class ScanSeeder {
 public:
  ScanSeeder(const OccupancyGrid& map, const ScanSeedingOptions& options);

  // The best pose of `points` (robot frame) anywhere in the map; nullopt below min_score.
  std::optional<CorrelativeMatch> Search(const std::vector<Eigen::Vector2f>& points) const;
  // Moves `fraction` of the particles (chosen at random) to a Gaussian around `pose`, at the
  // mean weight.
  void Seed(const Rigid2d& pose, std::vector<Particle>* particles, std::mt19937& rng) const;

 private:
  // The points Search uses: returns within max_range, at most max_points.
  std::vector<Eigen::Vector2f> SelectPoints(const std::vector<Eigen::Vector2f>& points) const;

  ScanSeedingOptions options_;
  std::unique_ptr<MatchGrid> grid_;
  std::unique_ptr<MatchGridPyramid> pyramid_;
  Rigid2d centre_;
  double half_extent_ = 0.0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_SCAN_SEEDING_H_
