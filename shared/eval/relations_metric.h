#ifndef FLEETMAP_SHARED_EVAL_RELATIONS_METRIC_H_
#define FLEETMAP_SHARED_EVAL_RELATIONS_METRIC_H_

#include <vector>

#include "shared/core/rigid2d.h"
#include "shared/core/trajectory.h"
#include "shared/eval/statistics.h"

namespace fleetmap {

// One line of a relations file: the pose of the scan at `to_timestamp` expressed in the frame of
// the scan at `from_timestamp` (Kümmerle et al. 2009, "On measuring the accuracy of SLAM
// algorithms").
struct Relation {
  double from_timestamp = 0.0;
  double to_timestamp = 0.0;
  Rigid2d expected;
};

struct RelationsOptions {
  // A relation's timestamps must equal a trajectory timestamp within this (seconds). The
  // benchmark's timestamps are scan ipc_timestamps printed to the microsecond.
  double timestamp_tolerance = 1e-6;
};

struct RelationsResult {
  int used = 0;
  int skipped = 0;               // a timestamp had no pose in the trajectory
  MeanStd translation;           // |t(error)|, metres
  MeanStd squared_translation;   // m^2
  MeanStd rotation_deg;          // |angle(error)|, degrees
  MeanStd squared_rotation_deg;  // deg^2
};

// For every relation with both poses present: error = (pose(t1)^-1 * pose(t2)) * expected^-1.
// The trajectory need not be sorted.
RelationsResult EvaluateRelations(const Trajectory& trajectory,
                                  const std::vector<Relation>& relations,
                                  const RelationsOptions& options = RelationsOptions());

// The error transform of one relation, exposed for tests and per-relation reports.
Rigid2d RelationError(const Rigid2d& from_pose, const Rigid2d& to_pose, const Rigid2d& expected);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_EVAL_RELATIONS_METRIC_H_
