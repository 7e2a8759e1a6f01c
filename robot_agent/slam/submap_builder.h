#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_BUILDER_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_BUILDER_H_

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shared/core/laser_scan.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/submap.h"

namespace fleetmap {

struct SubmapOptions {
  // A submap is finished after this many inserted scans or this much travel (metres) since its
  // first scan, whichever comes first. A value <= 0 disables that limit.
  int max_scans = 100;
  double max_travel = 10.0;
  OccupancyGridOptions grid;  // grid.max_trace_range bounds the submap's size
};

// Cuts a stream of (scan, pose) insertions into submaps and hands out snapshots of the ones that
// changed. Backend-neutral: the scan-matching backend feeds it its corrected poses; particle
// filters feed it their best particle's.
class SubmapBuilder {
 public:
  SubmapBuilder(std::string robot_id, const SubmapOptions& options);

  // Which submap a scan went into, and that submap's anchor (for a pose graph over submaps).
  struct Insertion {
    int64_t submap_id = 0;
    Rigid2d submap_in_local;
  };
  // Inserts a scan taken at `robot_in_local`. Starts a submap (anchored at this pose) when none
  // is active, and finishes it when the limits are reached. Empty when the pose is not finite
  // (nothing inserted).
  std::optional<Insertion> Insert(const LaserScan& scan, const Rigid2d& robot_in_local);
  // Finishes the active submap, if any.
  void FinishActive();
  // Moves a submap rigidly (e.g. after a loop closure): new anchor and scan poses, higher
  // revision. Only submaps still held (the active one, or ones not yet taken) can be revised;
  // returns false otherwise.
  bool Revise(int64_t submap_id, const Rigid2d& new_submap_in_local);

  // Snapshots of submaps changed since the last call, at most `max_count` (oldest first; the
  // rest stay for the next call); finished ones are then forgotten.
  std::vector<Submap> TakeUpdates(size_t max_count = std::numeric_limits<size_t>::max());

  const Submap* active() const { return active_ ? active_.get() : nullptr; }
  int64_t next_submap_id() const { return next_id_; }

 private:
  void FinishActiveInternal();

  std::string robot_id_;
  SubmapOptions options_;
  std::unique_ptr<Submap> active_;
  bool active_changed_ = false;
  double active_travel_ = 0.0;
  std::vector<Submap> finished_;  // finished but not yet taken
  int64_t next_id_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SUBMAP_BUILDER_H_
