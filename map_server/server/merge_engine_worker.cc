#include "map_server/server/merge_engine_worker.h"

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace fleetmap {
namespace {

constexpr char kEngineName[] = "merge-engine";

std::set<std::string> PlacedSet(const std::vector<RobotPlacementRecord>& placements) {
  std::set<std::string> placed;
  for (const auto& p : placements) {
    if (p.placed) placed.insert(p.robot_id);
  }
  return placed;
}

}  // namespace

MergeEngineWorker::MergeEngineWorker(const MergeEngineWorkerOptions& options, MapStore* store,
                                     VersionFeed* feed)
    : QueuedMergeWorker(options.common, store, feed),
      options_(options),
      engine_(std::make_unique<MergeEngine>(options.engine)) {}

MergeEngineWorker::~MergeEngineWorker() { Stop(); }

void MergeEngineWorker::Start() {
  // Serve the stored latest version (and its placements) at once; the engine is rebuilt from
  // the store on the worker thread, since re-aligning every robot is heavy.
  restored_ = store_->LatestVersion();
  if (restored_) {
    PublishStoredVersion(*restored_);
    SetPlacements(restored_->placements);
  }
  rebuild_pending_ = true;
  StartThread();
}

void MergeEngineWorker::Run() {
  const auto interval = std::chrono::duration<double>(common_options_.min_version_interval);
  while (true) {
    if (rebuild_pending_) {
      rebuild_pending_ = false;
      Rebuild(restored_ ? "startup: rebuilt from the store" : "startup");
    }
    auto event = queue_.PopWait(std::chrono::milliseconds(50));
    const bool drained = !event.has_value();
    // Apply what is queued, but run the engine and publish on time while uploads keep coming.
    const auto batch_start = std::chrono::steady_clock::now();
    while (event) {
      // Trajectory revisions come every few seconds while a robot drives or stands still; what
      // settles is the map: submaps, detections, robots.
      if (event->kind != MergeEvent::Kind::kTrajectoryStored) {
        settled_ = false;
        last_input_ = std::chrono::steady_clock::now();
      }
      Apply(*event);
      if (std::chrono::steady_clock::now() - batch_start >= interval) break;
      event = queue_.PopWait(std::chrono::milliseconds(0));
    }
    if (resync_needed_.exchange(false)) Rebuild("queue overflow: rebuilt from the store");
    // Searches postponed by the engine's per-update bounds continue while the queue is idle.
    if (engine_inputs_ || (!stopping_ && engine_->HasPendingWork())) RunEngine();
    const auto quiet = std::chrono::duration<double>(options_.settle_seconds);
    if (drained && !stopping_ && !settled_ && options_.settle_seconds > 0.0 &&
        !engine_->HasPendingWork() && std::chrono::steady_clock::now() - last_input_ >= quiet) {
      Settle();
    }
    const bool due = std::chrono::steady_clock::now() - last_publish_ >= interval;
    if (dirty_ && (due || stopping_)) PublishVersion();
    if (stopping_ && drained) break;
  }
}

void MergeEngineWorker::Apply(const MergeEvent& event) {
  switch (event.kind) {
    case MergeEvent::Kind::kRobotRegistered:
      ApplyRobot(event.robot_id);
      return;
    case MergeEvent::Kind::kSubmapStored:
      if (!event.submap) return;
      if (!robots_.count(event.robot_id)) ApplyRobot(event.robot_id);
      ApplySubmap(*event.submap);
      if (trigger_.empty()) trigger_ = "submaps";
      trigger_robots_.insert(event.robot_id);
      return;
    case MergeEvent::Kind::kTrajectoryStored:
      ApplyTrajectory(event.robot_id);
      return;
    case MergeEvent::Kind::kDetectionStored: {
      if (!event.detection) return;
      const RobotDetection& detection = event.detection->detection;
      if (!detection_seqs_.insert(event.detection->seq).second) return;
      new_detections_.push_back(DetectionRef{detection.observer_id, event.detection->detection_id});
      if (InvolvesLocalizationOnly(detection)) return;
      std::string error;
      if (!engine_->AddDetection(detection, &error)) {
        std::cerr << "fleetmap-server: merge engine refused detection "
                  << event.detection->detection_id << " of " << detection.observer_id << ": "
                  << error << "\n";
        return;
      }
      engine_inputs_ = true;
      return;
    }
  }
}

void MergeEngineWorker::ApplyRobot(const std::string& robot_id) {
  const std::optional<RobotRecord> robot = store_->GetRobot(robot_id);
  if (!robot) return;
  const auto old = robots_.find(robot_id);
  const bool known_before = old != robots_.end() && old->second.local_in_global.has_value();
  robots_[robot_id] = *robot;
  trigger_robots_.insert(robot_id);
  if (trigger_.empty()) trigger_ = "robot registered";
  // A robot localizing in a known map is not merged: it is where its poses say (placements).
  if (robot->localization_only) {
    if (known_before || engine_->RobotToGlobal(robot_id)) {
      Rebuild("robot re-registered for localization only: rebuilt from the store");
      return;
    }
  } else if (robot->local_in_global) {
    const bool same = known_before &&
                      old->second.local_in_global->translation() ==
                          robot->local_in_global->translation() &&
                      old->second.local_in_global->rotation() == robot->local_in_global->rotation();
    // The engine takes a known placement only before robots of unknown start are folded in,
    // and never moves one: otherwise start over with every known placement first.
    if (!same && (known_before || !engine_->SetKnownPlacement(robot_id, *robot->local_in_global))) {
      Rebuild("robot registered with a start pose: rebuilt from the store");
      return;
    }
  } else if (known_before) {
    Rebuild("robot re-registered without a start pose: rebuilt from the store");
    return;
  }
  RefreshPlacements();
  dirty_ = true;
}

void MergeEngineWorker::ApplySubmap(const StoredSubmap& stored) {
  covered_seq_ = std::max(covered_seq_, stored.seq);
  const Submap& submap = stored.submap;
  auto fed = submap_revisions_.find({submap.robot_id, submap.submap_id});
  if (fed != submap_revisions_.end() && fed->second >= submap.revision) return;
  new_submaps_.push_back(SubmapKey{submap.robot_id, submap.submap_id, submap.revision});
  std::string error;
  if (!engine_->AddOrUpdateSubmap(submap, &error)) {
    std::cerr << "fleetmap-server: merge engine refused submap " << submap.robot_id << "/"
              << submap.submap_id << " revision " << submap.revision << ": " << error << "\n";
    return;
  }
  submap_revisions_[{submap.robot_id, submap.submap_id}] = submap.revision;
  engine_inputs_ = true;
  dirty_ = true;  // the submap changes the map (if placed) or the unplaced counts
}

bool MergeEngineWorker::InvolvesLocalizationOnly(const RobotDetection& detection) const {
  for (const std::string& id : {detection.observer_id, detection.observed_id}) {
    const auto robot = robots_.find(id);
    if (robot != robots_.end() && robot->second.localization_only) return true;
  }
  return false;
}

void MergeEngineWorker::ApplyTrajectory(const std::string& robot_id) {
  if (const auto robot = robots_.find(robot_id);
      robot != robots_.end() && robot->second.localization_only) {
    return;  // not merged; its poses are already in the global frame
  }
  const std::optional<TrajectoryRecord> trajectory = store_->LatestTrajectory(robot_id);
  if (!trajectory) return;
  int64_t& known = trajectory_revisions_[robot_id];
  if (trajectory->revision <= known && known != 0) return;
  known = trajectory->revision;
  std::string error;
  if (!engine_->SetTrajectory(robot_id, trajectory->poses, &error)) {
    std::cerr << "fleetmap-server: merge engine refused the trajectory of " << robot_id << ": "
              << error << "\n";
    return;
  }
  engine_inputs_ = true;
}

void MergeEngineWorker::RunEngine() {
  engine_inputs_ = false;
  MergeUpdate update = engine_->Update();
  const std::set<std::string> placed_before = PlacedSet(Placements());
  NoteEvents(update.events, &status_);
  for (const AlignmentEvent& e : update.events) {
    // Joins and their undoing change what the map shows: worth a line in the server's log.
    if (e.type != AlignmentEventType::kAlignmentAccepted && e.type != AlignmentEventType::kWithdrawn) continue;
    std::cerr << "fleetmap-server: " << AlignmentEventTypeName(e.type) << " (" << EvidenceName(e.evidence)
              << "): " << e.robot_b << " with " << e.robot_a << "; " << e.reason.substr(0, 300) << "\n";
  }
  RefreshPlacements();
  const bool placements_changed = PlacedSet(Placements()) != placed_before;
  const bool has_news = std::any_of(update.events.begin(), update.events.end(), [](const auto& e) {
    return e.type != AlignmentEventType::kPending;
  });
  new_events_.insert(new_events_.end(), update.events.begin(), update.events.end());
  if (update.graph_changed || placements_changed || has_news) dirty_ = true;
}

void MergeEngineWorker::Rebuild(const std::string& trigger) {
  engine_ = std::make_unique<MergeEngine>(options_.engine);
  // Everything stored is folded in at once: no growth would come to end a probation.
  engine_->HoldMatchOnlyJoins(false);
  robots_.clear();
  trajectory_revisions_.clear();
  submap_revisions_.clear();
  detection_seqs_.clear();
  status_.clear();
  for (const RobotRecord& robot : store_->ListRobots()) {
    robots_[robot.robot_id] = robot;
    if (robot.local_in_global && !robot.localization_only) {
      engine_->SetKnownPlacement(robot.robot_id, *robot.local_in_global);
    }
  }
  // In ingest order, so the same robot defines the global frame as before the restart.
  std::vector<StoredSubmap> submaps = store_->LatestSubmaps("");
  std::sort(submaps.begin(), submaps.end(),
            [](const StoredSubmap& a, const StoredSubmap& b) { return a.seq < b.seq; });
  const std::vector<SubmapKey> pending = new_submaps_;
  for (const StoredSubmap& stored : submaps) ApplySubmap(stored);
  new_submaps_ = pending;  // provenance lists what is new, not what was re-fed
  for (const auto& [id, robot] : robots_) ApplyTrajectory(id);
  std::string error;
  for (const DetectionRecord& record : store_->DetectionsAfter(0)) {
    if (!detection_seqs_.insert(record.seq).second) continue;
    if (InvolvesLocalizationOnly(record.detection)) continue;
    if (!engine_->AddDetection(record.detection, &error)) continue;
  }
  // Fold everything in before serving placements, so a restart does not show robots unplaced.
  engine_inputs_ = true;
  const std::set<std::string> placed_before = PlacedSet(Placements());
  for (int pass = 0; pass < 10000 && !stopping_; ++pass) {
    RunEngine();
    if (!engine_->HasPendingWork()) break;
  }
  engine_->HoldMatchOnlyJoins(true);
  trigger_ = trigger;
  // After a restart a new version is needed only when the stored one is stale.
  const bool stale = !restored_ || restored_->covered_submap_seq < covered_seq_ ||
                     PlacedSet(Placements()) != PlacedSet(restored_->placements) ||
                     PlacedSet(Placements()) != placed_before;
  dirty_ = stale || !new_submaps_.empty();
  restored_.reset();
}

void MergeEngineWorker::Settle() {
  settled_ = true;
  const auto start = std::chrono::steady_clock::now();
  // Nothing more is coming to end a probation by growth: joins held on it are judged on the
  // maps as they are, as the rebuild below judges them.
  engine_->HoldMatchOnlyJoins(false);
  for (int pass = 0; pass < 10000 && !stopping_ && engine_->HasPendingWork(); ++pass) RunEngine();
  engine_->HoldMatchOnlyJoins(true);
  // What to fall back to.
  std::unique_ptr<MergeEngine> engine = std::move(engine_);
  const size_t placed_before = engine->PlacedRobots().size();
  auto robots = robots_;
  auto trajectory_revisions = trajectory_revisions_;
  auto submap_revisions = submap_revisions_;
  auto detection_seqs = detection_seqs_;
  auto status = status_;
  const size_t events = new_events_.size();
  const bool dirty = dirty_;
  const std::string trigger = trigger_;
  Rebuild("uploads settled: rebuilt from the store");
  const size_t placed_after = engine_->PlacedRobots().size();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // A rebuild cut short by a shutdown is not the whole store's merge.
  const bool keep = !stopping_ && placed_after >= placed_before;
  if (!keep) {
    engine_ = std::move(engine);
    robots_ = std::move(robots);
    trajectory_revisions_ = std::move(trajectory_revisions);
    submap_revisions_ = std::move(submap_revisions);
    detection_seqs_ = std::move(detection_seqs);
    status_ = std::move(status);
    new_events_.resize(events);
    dirty_ = dirty;
    trigger_ = trigger;
    RefreshPlacements();
  }
  std::ostringstream outcome;
  outcome << "rebuilt from the store in " << std::fixed << std::setprecision(1) << seconds
          << " s, placing " << placed_after << " robot(s) against " << placed_before << " as fed";
  std::cerr << "fleetmap-server: uploads settled: " << outcome.str()
            << (keep ? "; the rebuild is kept" : "; the merge as fed is kept") << "\n";
  // The version history says the check was made, and how the two merges compared.
  if (keep) {
    trigger_ = "uploads settled: " + outcome.str();
  } else if (!stopping_) {
    trigger_ = "uploads settled: the merge as fed is kept (" + outcome.str() + ")";
    dirty_ = true;
  }
}

void MergeEngineWorker::RefreshPlacements() {
  std::vector<RobotPlacementRecord> placements = MakePlacements(robots_, *engine_, status_);
  SetPlacements(std::move(placements));
}

void MergeEngineWorker::PublishVersion() {
  VersionRecord info = PendingVersion("merge update", kEngineName);
  info.quality["submaps_placed"] = static_cast<double>(engine_->SubmapPoses().size());
  AddEngineProvenance(new_events_, engine_->Quality(), &info);
  // A rebuild re-makes every join: say first that it was a rebuild.
  if (!trigger_.empty() && trigger_.find("rebuilt from the store") != std::string::npos &&
      info.trigger != trigger_) {
    info.trigger = trigger_ + "; " + info.trigger;
  }
  std::string error;
  std::optional<OccupancyGrid> grid =
      engine_->RenderGlobalMap(std::nullopt, common_options_.resolution, &error);
  if (!grid) {
    if (!error.empty()) std::cerr << "fleetmap-server: rendering failed: " << error << "\n";
    OccupancyGridOptions empty;
    empty.resolution = common_options_.resolution;
    grid.emplace(empty);
  }
  if (StoreAndPublish(std::move(info), *grid)) new_events_.clear();
}

}  // namespace fleetmap
