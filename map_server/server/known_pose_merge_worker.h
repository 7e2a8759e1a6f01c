#ifndef FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_
#define FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "map_server/server/bounded_queue.h"
#include "map_server/server/merge_worker.h"
#include "map_server/server/version_feed.h"
#include "map_server/store/map_store.h"

namespace fleetmap {

struct KnownPoseMergeWorkerOptions {
  size_t queue_capacity = 4096;
  // Uploads arriving within this time are folded into one version (seconds).
  double min_version_interval = 0.5;
  double resolution = 0.05;     // of the global map, metres per cell
  float log_odds_limit = 6.0f;  // published cells are clamped to +-this
  int zstd_level = 1;
};

// The first MergeWorker: a robot registered with `local_in_global` is placed there; its
// submaps are fused into the global map at local_in_global * submap_in_local. Robots without a
// start pose stay unplaced (listed as such in every version's placements) until the merge
// engine replaces this worker.
class KnownPoseMergeWorker : public MergeWorker {
 public:
  KnownPoseMergeWorker(const KnownPoseMergeWorkerOptions& options, MapStore* store,
                       VersionFeed* feed);
  ~KnownPoseMergeWorker() override;

  void Start() override;
  void Stop() override;
  void Submit(MergeEvent event) override;
  std::vector<RobotPlacementRecord> Placements() const override;

 private:
  using SubmapId = std::pair<std::string, int64_t>;
  struct Rendered {
    int64_t revision = 0;
    Rigid2d submap_in_global;
  };

  void Run();
  void Apply(const MergeEvent& event);
  void ApplySubmap(const StoredSubmap& stored);
  // Re-renders everything from the store (start, queue overflow, a robot moved).
  void Rebuild(const std::string& trigger);
  void RefreshPlacements();
  void PublishVersion();
  std::optional<Rigid2d> LocalInGlobal(const std::string& robot_id) const;

  const KnownPoseMergeWorkerOptions options_;
  MapStore* const store_;
  VersionFeed* const feed_;
  BoundedQueue<MergeEvent> queue_;
  std::atomic<bool> resync_needed_{false};
  std::atomic<bool> stopping_{false};
  std::thread thread_;

  // Owned by the worker thread (and by Start() before the thread exists).
  OccupancyGrid canvas_;
  std::map<SubmapId, Rendered> rendered_;
  std::map<std::string, RobotRecord> robots_;
  int64_t covered_seq_ = 0;
  int64_t unplaced_submaps_ = 0;
  bool dirty_ = false;
  std::string trigger_;
  std::set<std::string> trigger_robots_;
  std::vector<SubmapKey> new_submaps_;
  std::vector<DetectionRef> new_detections_;
  std::chrono::steady_clock::time_point last_publish_;

  mutable std::mutex placements_mutex_;  // guards placements_ (read by RPC threads)
  std::vector<RobotPlacementRecord> placements_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_KNOWN_POSE_MERGE_WORKER_H_
