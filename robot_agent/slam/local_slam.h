#ifndef FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_SLAM_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_SLAM_H_

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

// What every local SLAM backend (scan matching, grid FastSLAM, Rao-Blackwellized PF) offers the
// robot agent and the offline tool. Inputs arrive in time order; the backend keeps a pose for
// every scan it was given and cuts its map into submaps that the agent uploads.
//
// Frames: odometry poses are robot-in-odometry-frame; every output pose is robot-in-local-map,
// the robot's own map frame (it starts at the first scan's pose, identity).
class LocalSlam {
 public:
  virtual ~LocalSlam() = default;

  // One odometry reading. Returns false (and says why) when it is older than the previous input
  // or not finite; the backend state is then unchanged.
  virtual bool AddOdometry(const StampedPose& odometry, std::string* error) = 0;

  // One laser scan, stamped with its acquisition time. The backend interpolates odometry at
  // scan.timestamp (holding the nearest reading when the scan lies outside them; with no
  // odometry at all it assumes the robot may have moved anywhere within its search window).
  // A scan with no returns still gets a pose (carried by odometry). Returns false, unchanged,
  // when the scan is older than the previous input or malformed.
  virtual bool AddScan(const LaserScan& scan, std::string* error) = 0;

  // Robot in the local map at the latest scan.
  virtual Rigid2d CurrentPose() const = 0;

  // One pose per scan added, in order, with the scan's timestamp. Backends that revise earlier
  // poses (loop closure, resampling) update them here and bump trajectory_revision().
  virtual const Trajectory& trajectory() const = 0;
  virtual int64_t trajectory_revision() const = 0;

  // Submaps that are new, changed or finished since the previous call, as snapshots. A submap
  // is reported again with a higher `revision` when the backend changes its mind about it.
  std::vector<Submap> TakeSubmapUpdates() {
    return TakeSubmapUpdates(std::numeric_limits<size_t>::max());
  }
  // The same, at most `max_count` of them; the rest come with the next calls. A caller that
  // keeps every submap takes a few at a time, so that a loop closure that moves all of them
  // never holds each grid twice (the caller's copy and its new rendering).
  virtual std::vector<Submap> TakeSubmapUpdates(size_t max_count) = 0;

  // End of input: finishes the active submap, so the next TakeSubmapUpdates() returns it.
  virtual void Finish() = 0;

  // A one-line human-readable summary of what the backend did (matches, failures, ...).
  virtual std::string Statistics() const = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_LOCAL_SLAM_H_
