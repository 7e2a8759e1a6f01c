#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_LASER_BODY_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_LASER_BODY_H_

#include <vector>

#include <Eigen/Core>

#include "robot_agent/detection/circle_fit.h"
#include "robot_agent/detection/laser_fusion.h"
#include "shared/core/laser_scan.h"

namespace fleetmap {

// A run of consecutive returns that belong to one object.
struct BeamRun {
  int first = 0;  // beam indices, inclusive
  int last = 0;
};

// Splits the scan into runs of returns that belong to one object: consecutive returns further
// apart than max(min_jump, jump_beams * beam spacing) belong to different objects.
std::vector<BeamRun> SplitIntoRuns(const LaserScan& scan, const LaserFusionOptions& options);

// The return of beam i as a direction and a range, in the sensor frame.
BeamReturn BeamAt(const LaserScan& scan, int i);

// Checks that `segment` is a free-standing body of the known radius and fits it: narrow, in
// front of its surroundings (or hidden on one side by something nearer), round rather than flat.
// The segment may grow by neighbouring returns that lie on the fitted circle (it is updated);
// `returns` is how many the fit used.
FusionStatus MeasureBody(const LaserScan& scan, BeamRun* segment, double body_radius,
                         const LaserFusionOptions& options, CircleFit* fit, int* returns);

struct LaserBodyOptions {
  LaserFusionOptions fusion;
  // Without a camera to confirm it, a body must have this many returns. Four or five are not
  // enough: in the simulated department the end of a 0.2 m thick wall seen with a piece of its
  // side passes every test of a body (docs/BENCHMARKS.md).
  int min_returns = 6;
  // ... and fit the circle closely: RMS at most this many range-noise sigmas (a 0.3 m box seen
  // corner-on fits a 0.2 m circle within 2.5 cm).
  double max_rms_sigmas = 2.0;
  // ... and a line must fit them clearly worse than the circle: RMS at least this many sigmas
  // and twice the circle's (flat pieces of wall standing out of a doorway otherwise pass).
  double min_line_rms_sigmas = 1.5;
};

// Free-standing round bodies of the given radius in the scan, found by the laser alone: the
// centres, in the robot frame. Other robots are the case in point: one beside or behind the
// camera's view is still in the laser's, and its returns must not be mapped as walls.
std::vector<Eigen::Vector2d> FindLaserBodies(const LaserScan& scan, double body_radius,
                                             const LaserBodyOptions& options = LaserBodyOptions());

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_LASER_BODY_H_
