#ifndef FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_
#define FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_

#include <map>
#include <optional>
#include <string>
#include <utility>

#include "map_server/server/queued_merge_worker.h"

namespace fleetmap {

// The first MergeWorker: a robot registered with `local_in_global` is placed there; its
// submaps are fused into the global map at local_in_global * submap_in_local. Robots without a
// start pose stay unplaced (listed as such in every version's placements): placing them is the
// merge engine's worker's job (MergeEngineWorker, the server's default).
class KnownPoseMergeWorker : public QueuedMergeWorker {
 public:
  KnownPoseMergeWorker(const MergeWorkerOptions& options, MapStore* store, VersionFeed* feed);
  ~KnownPoseMergeWorker() override;

  void Start() override;

 private:
  using SubmapId = std::pair<std::string, int64_t>;
  struct Rendered {
    int64_t revision = 0;
    Rigid2d submap_in_global;
  };

  void Run() override;
  void Apply(const MergeEvent& event);
  void ApplySubmap(const StoredSubmap& stored);
  // Re-renders everything from the store (start, queue overflow, a robot moved).
  void Rebuild(const std::string& trigger);
  void RefreshPlacements();
  void PublishVersion();
  std::optional<Rigid2d> LocalInGlobal(const std::string& robot_id) const;

  // Owned by the worker thread (and by Start() before the thread exists).
  OccupancyGrid canvas_;
  std::map<SubmapId, Rendered> rendered_;
  std::map<std::string, RobotRecord> robots_;
  int64_t unplaced_submaps_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_
