#ifndef FLEETMAP_SHARED_MATCHING_CORRELATIVE_SEARCH_H_
#define FLEETMAP_SHARED_MATCHING_CORRELATIVE_SEARCH_H_

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"
#include "shared/matching/match_grid.h"
#include "shared/matching/match_grid_pyramid.h"

namespace fleetmap {

struct CorrelativeSearchOptions {
  double linear_window = 0.3;    // metres searched either side of the guess, in x and in y
  double angular_window = 0.35;  // radians searched either side of the guess
  // Angular step (radians); 0 derives it from the farthest point so that it moves about one cell.
  double angular_step = 0.0;
  // Mean per-point score (0..1) below which no match is reported.
  double min_score = 0.0;
  // Brute-force search only: multiplies the score by exp(-(w_t * |dt|^2 + w_r * |dr|^2)) so that
  // equally good poses resolve towards the guess (a corridor should not slide along its axis).
  double translation_penalty = 0.5;  // per m^2
  double rotation_penalty = 0.5;     // per rad^2
};

struct CorrelativeMatch {
  Rigid2d pose;        // robot (points' frame) in the map
  double score = 0.0;  // mean per-point score, 0..1
};

// Exhaustive search over the window on the grid's own cells: cheap for small windows, no
// precomputation, so it suits a local map that changes at every scan.
std::optional<CorrelativeMatch> SearchBruteForce(const std::vector<Eigen::Vector2f>& points,
                                                 const MatchGrid& grid, const Rigid2d& guess,
                                                 const CorrelativeSearchOptions& options);

// Branch and bound over a precomputed pyramid: exact best (quantised) score over large windows
// (metres, tens of degrees) in milliseconds; the tool for loop closure and map merging.
std::optional<CorrelativeMatch> SearchBranchAndBound(const std::vector<Eigen::Vector2f>& points,
                                                     const MatchGridPyramid& pyramid,
                                                     const Rigid2d& guess,
                                                     const CorrelativeSearchOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_CORRELATIVE_SEARCH_H_
