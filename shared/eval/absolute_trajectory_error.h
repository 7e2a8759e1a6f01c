#ifndef FLEETMAP_SHARED_EVAL_ABSOLUTE_TRAJECTORY_ERROR_H_
#define FLEETMAP_SHARED_EVAL_ABSOLUTE_TRAJECTORY_ERROR_H_

#include <optional>

#include "shared/core/rigid2d.h"
#include "shared/core/trajectory.h"
#include "shared/eval/statistics.h"

namespace fleetmap {

struct AteOptions {
  // Each estimated pose is paired with the ground-truth pose nearest in time, if this close
  // (seconds). Corrected logs print timestamps to ~6 significant digits, hence not 1 us.
  double max_time_difference = 0.01;
  // Rigidly align the estimate to the ground truth first (closed-form 2D Horn/Umeyama on the
  // paired positions). Without it the two must share a frame.
  bool align = false;
};

struct AteResult {
  int matched = 0;
  int unmatched = 0;              // estimated poses with no ground truth close enough in time
  double rmse_translation = 0.0;  // metres
  double rmse_rotation_deg = 0.0;
  MeanStd translation;                 // per-pose position error, metres
  Rigid2d ground_truth_from_estimate;  // the alignment applied (identity without align)
};

// Absolute trajectory error. Returns nullopt when fewer than one pair (two with `align`)
// matches, or when alignment is degenerate (all paired positions equal).
std::optional<AteResult> EvaluateAte(const Trajectory& estimate, const Trajectory& ground_truth,
                                     const AteOptions& options = AteOptions());

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_ABSOLUTE_TRAJECTORY_ERROR_H_
