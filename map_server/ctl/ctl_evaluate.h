#ifndef FLEETMAP_MAP_SERVER_CTL_CTL_EVALUATE_H_
#define FLEETMAP_MAP_SERVER_CTL_CTL_EVALUATE_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "map_server/ctl/ctl_commands.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct EvaluateOptions {
  // YAML with `robots: [{name: ID, start: {x, y, theta}}, ...]`: each robot's true start pose
  // in the world (its local map frame's pose). The simulator's manifest.yaml is such a file.
  std::string ground_truth;
  // Optional: the global map as exported by `fleetmapctl export` (YAML), and the true world
  // map (YAML); with both, occupied cells of the global map are scored against the true walls.
  std::string map;
  std::string world;
  int tolerance_cells = 1;  // "within one cell of a true wall": see WallMask
  // Robots localizing in the global map, each as "ID=TRUE_TRAJECTORY" (the simulator's
  // <robot>.gt.txt of the robot it drove): their poses are scored in the world, through the
  // reference robot's placement.
  std::vector<std::string> localized;
};

// How far one robot's placement is from the truth, relative to the reference robot.
struct PairError {
  std::string reference;
  std::string robot;
  double translation_error = 0.0;  // metres
  double rotation_error = 0.0;     // radians
};

struct MergeEvaluation {
  std::vector<PairError> pairs;
  std::vector<std::string> unplaced;  // robots in the ground truth the server has not placed
  std::optional<double> map_accuracy;  // share of occupied cells within tolerance of a wall
  // The same at the best rigid placement near the reference robot's (FitMapToWalls).
  std::optional<double> map_accuracy_best_fit;
  long occupied_cells = 0;
};

// Pure scoring: placements (local frame in global) against true start poses (local frame in
// world). The first placed robot (in name order) is the reference.
MergeEvaluation EvaluatePlacements(const std::map<std::string, Rigid2d>& placements,
                                   const std::map<std::string, Rigid2d>& truth);
// Reads true start poses from a ground-truth YAML; false with `error` on a bad file.
bool ReadStartPoses(const std::string& path, std::map<std::string, Rigid2d>* starts,
                    std::string* error);

int RunEvaluate(const CtlContext& context, const EvaluateOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_CTL_CTL_EVALUATE_H_
