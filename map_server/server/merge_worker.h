#ifndef FLEETMAP_MAP_SERVER_SERVER_MERGE_WORKER_H_
#define FLEETMAP_MAP_SERVER_SERVER_MERGE_WORKER_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "map_server/store/records.h"

namespace fleetmap {

// Something the store has just committed; the merge worker folds it into the global map.
struct MergeEvent {
  enum class Kind { kRobotRegistered, kSubmapStored, kTrajectoryStored, kDetectionStored };
  Kind kind = Kind::kSubmapStored;
  std::string robot_id;                         // the robot concerned (observer for detections)
  std::shared_ptr<const StoredSubmap> submap;   // kSubmapStored
  std::optional<DetectionRecord> detection;     // kDetectionStored
};

// The component that owns the global map: a single worker thread fed by a bounded queue. It
// places robots in the global frame, renders the map, stores each new version (with its
// provenance) in the MapStore and publishes it to the VersionFeed. Handlers only Submit().
//
// The first implementation (KnownPoseMergeWorker) places robots registered with a start pose;
// the merge engine (issue 8) provides another implementation behind this interface.
class MergeWorker {
 public:
  virtual ~MergeWorker() = default;

  // Loads the state from the store and starts the thread; publishes a version when the store
  // holds data that no stored version covers (e.g. acknowledged just before a crash).
  virtual void Start() = 0;
  // Finishes pending work (publishing a last version if needed) and joins the thread.
  virtual void Stop() = 0;
  // Never blocks. When the queue is full the event is dropped and the worker rebuilds from the
  // store on its next pass, so a committed item is never lost.
  virtual void Submit(MergeEvent event) = 0;
  // Where each registered robot currently stands (may be newer than the latest version).
  virtual std::vector<RobotPlacementRecord> Placements() const = 0;
};

// Where a robot that localizes in a known map stands (RobotRecord::localization_only): its
// poses are in that map's frame, placed by its registration (identity: the global map itself).
// Both workers leave it out of the merge and report this.
inline RobotPlacementRecord LocalizationPlacement(const RobotRecord& robot) {
  RobotPlacementRecord p;
  p.robot_id = robot.robot_id;
  p.placed = true;
  p.local_in_global = robot.local_in_global.value_or(Rigid2d());
  p.start_in_global = p.local_in_global;
  p.source = "localization";
  p.note = "localizes in a known map; not merged, its poses are in that map's frame";
  return p;
}

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_MERGE_WORKER_H_
