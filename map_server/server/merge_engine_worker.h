#ifndef FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_WORKER_H_
#define FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_WORKER_H_

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "map_server/merge/merge_engine.h"
#include "map_server/server/merge_engine_provenance.h"
#include "map_server/server/queued_merge_worker.h"

namespace fleetmap {

struct MergeEngineWorkerOptions {
  MergeWorkerOptions common;
  MergeEngineOptions engine;
  // Once no submap, detection or robot registration has come for this long, the engine is
  // rebuilt from the store with everything at once, and the rebuild kept when it places at least
  // as many robots. Fed as uploads come, a submap is matched against the maps of that moment, at
  // the revision of that moment, and which join comes first depends on arrival order: with
  // detections the department maps gained 0.2-2.4 points rebuilt (docs/BENCHMARKS.md, issue 8,
  // session 24). Longer than a robot's gaps between finished submaps while it drives in real
  // time (about 20 s in the simulator's department; trajectory revisions do not count), since a
  // rebuild redoes every search. 0: never.
  double settle_seconds = 30.0;
};

// The MergeWorker that merges robots of unknown start (issue 8): one thread owns a MergeEngine
// fed from the bounded queue with the stored submaps, trajectories and detections; after each
// engine Update() that changed the map it renders, stores and publishes a new version whose
// provenance lists the engine's alignment events and quality figures. Robots registered with a
// start pose are held there (MergeEngine::SetKnownPlacement), as with KnownPoseMergeWorker.
// On start and on queue overflow the engine is rebuilt from the store, and once uploads settle
// (settle_seconds).
class MergeEngineWorker : public QueuedMergeWorker {
 public:
  MergeEngineWorker(const MergeEngineWorkerOptions& options, MapStore* store, VersionFeed* feed);
  ~MergeEngineWorker() override;

  void Start() override;

 private:
  void Run() override;
  void Apply(const MergeEvent& event);
  void ApplyRobot(const std::string& robot_id);
  void ApplySubmap(const StoredSubmap& stored);
  void ApplyTrajectory(const std::string& robot_id);
  // Detections to or from a robot localizing in a known map: the engine, which merges the
  // robots' own maps, has no use for them (they are stored, and listed in the provenance).
  bool InvolvesLocalizationOnly(const RobotDetection& detection) const;
  // Runs the engine once and records what it did; false when nothing changed.
  void RunEngine();
  // A fresh engine fed with everything in the store.
  void Rebuild(const std::string& trigger);
  // Rebuild() once uploads have settled; the engine as fed is kept when it placed more robots.
  void Settle();
  void RefreshPlacements();
  void PublishVersion();

  const MergeEngineWorkerOptions options_;

  // Owned by the worker thread (and by Start() before the thread exists).
  std::unique_ptr<MergeEngine> engine_;
  std::map<std::string, RobotRecord> robots_;
  std::map<std::string, int64_t> trajectory_revisions_;
  // What the engine already has, so events replayed after a rebuild are not fed twice.
  std::map<std::pair<std::string, int64_t>, int64_t> submap_revisions_;
  std::set<int64_t> detection_seqs_;
  std::map<std::string, RobotMergeStatus> status_;  // why each robot is (un)placed
  std::optional<VersionRecord> restored_;  // the stored version served until the first rebuild
  bool rebuild_pending_ = false;
  bool engine_inputs_ = false;  // the engine got data since its last Update()
  bool settled_ = true;  // no submap, detection or robot since the last Settle() (or the start)
  std::chrono::steady_clock::time_point last_input_;
  std::vector<AlignmentEvent> new_events_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_WORKER_H_
