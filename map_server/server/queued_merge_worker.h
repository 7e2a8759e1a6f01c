#ifndef FLEETMAP_MAP_SERVER_SERVER_QUEUED_MERGE_WORKER_H_
#define FLEETMAP_MAP_SERVER_SERVER_QUEUED_MERGE_WORKER_H_

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server/bounded_queue.h"
#include "map_server/server/merge_worker.h"
#include "map_server/server/version_feed.h"
#include "map_server/store/map_store.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// Queue, version pacing and map encoding: what both merge workers take.
struct MergeWorkerOptions {
  size_t queue_capacity = 4096;
  // Uploads arriving within this time are folded into one version (seconds).
  double min_version_interval = 0.5;
  double resolution = 0.05;     // of the global map, metres per cell
  float log_odds_limit = 6.0f;  // published cells are clamped to +-this
  int zstd_level = 1;
};

// What both merge workers share: the bounded queue their one thread drains, the placements the
// RPC threads read, and the next version's pending provenance with its storing and publishing.
// A derived worker implements Start() (which ends with StartThread()) and Run(), and calls Stop()
// in its destructor, while its own members still exist.
class QueuedMergeWorker : public MergeWorker {
 public:
  void Stop() final;
  void Submit(MergeEvent event) final;
  std::vector<RobotPlacementRecord> Placements() const final;

 protected:
  QueuedMergeWorker(const MergeWorkerOptions& options, MapStore* store, VersionFeed* feed);

  void StartThread();
  // The worker thread's loop; returns once stopping_ is set and the queue is drained.
  virtual void Run() = 0;
  void SetPlacements(std::vector<RobotPlacementRecord> placements);
  // Serves a stored version as it is (a restart); false when its grid cannot be read.
  bool PublishStoredVersion(const VersionRecord& version);
  // The next version's record: the pending provenance, the placements and how many are placed.
  VersionRecord PendingVersion(const std::string& default_trigger, const std::string& engine) const;
  // Stores `info` with `canvas` (clamped, cropped and compressed) and publishes it; the pending
  // provenance is cleared once stored, and kept for the next pass when storing fails.
  bool StoreAndPublish(VersionRecord info, const OccupancyGrid& canvas);

  const MergeWorkerOptions common_options_;
  MapStore* const store_;
  VersionFeed* const feed_;
  BoundedQueue<MergeEvent> queue_;
  std::atomic<bool> resync_needed_{false};
  std::atomic<bool> stopping_{false};

  // Owned by the worker thread (and by Start() before the thread exists).
  int64_t covered_seq_ = 0;
  bool dirty_ = false;
  std::string trigger_;
  std::set<std::string> trigger_robots_;
  std::vector<SubmapKey> new_submaps_;
  std::vector<DetectionRef> new_detections_;
  std::chrono::steady_clock::time_point last_publish_;

 private:
  std::thread thread_;
  mutable std::mutex placements_mutex_;  // guards placements_ (read by RPC threads)
  std::vector<RobotPlacementRecord> placements_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_QUEUED_MERGE_WORKER_H_
