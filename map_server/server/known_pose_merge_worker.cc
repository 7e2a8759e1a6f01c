#include "map_server/server/known_pose_merge_worker.h"

#include <utility>

#include "map_server/server/global_map_renderer.h"

namespace fleetmap {
namespace {

constexpr char kEngineName[] = "known-start-pose";

OccupancyGrid EmptyCanvas(double resolution) {
  OccupancyGridOptions options;
  options.resolution = resolution;
  return OccupancyGrid(options);
}

}  // namespace

KnownPoseMergeWorker::KnownPoseMergeWorker(const MergeWorkerOptions& options, MapStore* store,
                                           VersionFeed* feed)
    : QueuedMergeWorker(options, store, feed), canvas_(EmptyCanvas(options.resolution)) {}

KnownPoseMergeWorker::~KnownPoseMergeWorker() { Stop(); }

void KnownPoseMergeWorker::Start() {
  const std::optional<VersionRecord> latest = store_->LatestVersion();
  Rebuild("startup: rebuilt from the store");
  // Serve the stored latest version as it is, unless acknowledged data is missing from it.
  const bool published =
      latest && latest->covered_submap_seq >= covered_seq_ && PublishStoredVersion(*latest);
  if (!published && (covered_seq_ > 0 || !robots_.empty())) PublishVersion();
  dirty_ = false;
  trigger_.clear();
  trigger_robots_.clear();
  new_submaps_.clear();
  StartThread();
}

void KnownPoseMergeWorker::Run() {
  const auto interval = std::chrono::duration<double>(common_options_.min_version_interval);
  while (true) {
    auto event = queue_.PopWait(std::chrono::milliseconds(50));
    const bool drained = !event.has_value();
    // Apply what is queued, but publish on time even while uploads keep coming.
    while (event) {
      Apply(*event);
      if (std::chrono::steady_clock::now() - last_publish_ >= interval && dirty_) break;
      event = queue_.PopWait(std::chrono::milliseconds(0));
    }
    if (resync_needed_.exchange(false)) Rebuild("queue overflow: rebuilt from the store");
    const bool due = std::chrono::steady_clock::now() - last_publish_ >= interval;
    if (dirty_ && (due || stopping_)) PublishVersion();
    if (stopping_ && drained) break;
  }
}

std::optional<Rigid2d> KnownPoseMergeWorker::LocalInGlobal(const std::string& robot_id) const {
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return std::nullopt;
  return it->second.local_in_global;
}

void KnownPoseMergeWorker::Apply(const MergeEvent& event) {
  switch (event.kind) {
    case MergeEvent::Kind::kRobotRegistered: {
      const std::optional<RobotRecord> robot = store_->GetRobot(event.robot_id);
      if (!robot) return;
      auto old = robots_.find(event.robot_id);
      const bool moved =
          old != robots_.end() &&
          (old->second.local_in_global.has_value() != robot->local_in_global.has_value() ||
           (robot->local_in_global &&
            (old->second.local_in_global->translation() != robot->local_in_global->translation() ||
             old->second.local_in_global->rotation() != robot->local_in_global->rotation())));
      robots_[event.robot_id] = *robot;
      if (moved) {
        Rebuild("robot re-registered with a new start pose");
      } else {
        RefreshPlacements();
        if (trigger_.empty()) trigger_ = "robot registered";
      }
      trigger_robots_.insert(event.robot_id);
      dirty_ = true;
      return;
    }
    case MergeEvent::Kind::kSubmapStored:
      if (!event.submap) return;
      if (!robots_.count(event.robot_id)) {
        if (auto robot = store_->GetRobot(event.robot_id)) robots_[event.robot_id] = *robot;
        RefreshPlacements();
      }
      ApplySubmap(*event.submap);
      if (trigger_.empty()) trigger_ = "submaps";
      trigger_robots_.insert(event.robot_id);
      dirty_ = true;
      return;
    case MergeEvent::Kind::kDetectionStored:
      // Known start poses need no detections; they are listed in the next version's provenance
      // for the merge engine's benefit but do not trigger a version on their own.
      if (event.detection) {
        new_detections_.push_back(
            DetectionRef{event.detection->detection.observer_id, event.detection->detection_id});
      }
      return;
    case MergeEvent::Kind::kTrajectoryStored:
      return;  // robot poses are read from the store when queried
  }
}

void KnownPoseMergeWorker::ApplySubmap(const StoredSubmap& stored) {
  const Submap& submap = stored.submap;
  covered_seq_ = std::max(covered_seq_, stored.seq);
  new_submaps_.push_back(SubmapKey{submap.robot_id, submap.submap_id, submap.revision});
  const std::optional<Rigid2d> local_in_global = LocalInGlobal(submap.robot_id);
  const SubmapId id{submap.robot_id, submap.submap_id};
  if (!local_in_global) {
    ++unplaced_submaps_;
    return;
  }
  auto it = rendered_.find(id);
  if (it != rendered_.end()) {
    if (it->second.revision >= submap.revision) return;  // a late event for an older revision
    // Take the superseded revision out before adding the new one.
    const auto old = store_->GetSubmap(SubmapKey{id.first, id.second, it->second.revision});
    if (old) FuseSubmap(old->submap.grid, it->second.submap_in_global, -1.0f, &canvas_);
  }
  const Rigid2d submap_in_global = *local_in_global * submap.submap_in_local;
  FuseSubmap(submap.grid, submap_in_global, 1.0f, &canvas_);
  rendered_[id] = Rendered{submap.revision, submap_in_global};
}

void KnownPoseMergeWorker::Rebuild(const std::string& trigger) {
  canvas_ = EmptyCanvas(common_options_.resolution);
  rendered_.clear();
  robots_.clear();
  unplaced_submaps_ = 0;
  for (const RobotRecord& robot : store_->ListRobots()) robots_[robot.robot_id] = robot;
  RefreshPlacements();
  const std::vector<SubmapKey> pending = new_submaps_;
  for (const StoredSubmap& stored : store_->LatestSubmaps("")) ApplySubmap(stored);
  new_submaps_ = pending;  // provenance lists what is new, not what was re-rendered
  trigger_ = trigger;
  dirty_ = true;
}

void KnownPoseMergeWorker::RefreshPlacements() {
  std::vector<RobotPlacementRecord> placements;
  for (const auto& [id, robot] : robots_) {
    RobotPlacementRecord p;
    p.robot_id = id;
    p.placed = robot.local_in_global.has_value();
    if (robot.localization_only) {
      p = LocalizationPlacement(robot);
    } else if (p.placed) {
      p.local_in_global = *robot.local_in_global;
      p.start_in_global = *robot.local_in_global;  // held there: no drift to follow
      p.source = "registration";
    } else {
      p.source = "unplaced";
      p.note = "no start pose registered; waiting for the merge engine";
    }
    placements.push_back(std::move(p));
  }
  SetPlacements(std::move(placements));
}

void KnownPoseMergeWorker::PublishVersion() {
  VersionRecord info = PendingVersion("update", kEngineName);
  info.quality["submaps_rendered"] = static_cast<double>(rendered_.size());
  info.quality["submaps_unplaced"] = static_cast<double>(unplaced_submaps_);
  StoreAndPublish(std::move(info), canvas_);
}

}  // namespace fleetmap
