#ifndef FLEETMAP_SHARED_MATCHING_SCAN_SEGMENTS_H_
#define FLEETMAP_SHARED_MATCHING_SCAN_SEGMENTS_H_

#include <vector>

#include <Eigen/Core>

#include "shared/matching/surface_elements.h"

namespace fleetmap {

struct ScanSegmentOptions {
  // Consecutive returns closer than this are left to FitSurfaceElements; farther than
  // max_gap they are never joined (metres).
  double min_gap = 0.1;
  double max_gap = 1.0;
  // Adaptive breakpoint test (Borges & Aldon): two consecutive returns lie on one surface when
  // their gap is no larger than a surface seen at this incidence angle (radians) would give,
  // plus the range noise; larger gaps are depth jumps (a door, an object in front of a wall).
  double min_incidence = 0.087;  // 5 degrees
  double range_noise = 0.03;
  // Consecutive returns seen more than this far apart in bearing (radians) are not joined:
  // beams between them saw nothing.
  double max_bearing_step = 0.06;
};

// Segment elements joining consecutive returns of one scan (points in beam order, seen from
// `origin`) that lie on one surface but too far apart for FitSurfaceElements to join. Why: far
// down a wall seen at a shallow angle a scan's returns are tens of centimetres apart, and the
// next scan's beams hit that wall just as far along as the robot moved; matched against
// isolated points, each return finds its own beam's previous hit and holds the robot back by
// the whole move (two exact scans 0.1 m apart in a room matched 5 cm short).
std::vector<SurfaceElement> JoinConsecutiveReturns(const std::vector<Eigen::Vector2d>& points_in_beam_order,
                                                   const Eigen::Vector2d& origin,
                                                   const ScanSegmentOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_SCAN_SEGMENTS_H_
