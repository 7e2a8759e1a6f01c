#include "map_server/server/queued_merge_worker.h"

#include <iostream>
#include <memory>
#include <utility>

#include "shared/codec/grid_codec.h"

namespace fleetmap {

QueuedMergeWorker::QueuedMergeWorker(const MergeWorkerOptions& options, MapStore* store,
                                     VersionFeed* feed)
    : common_options_(options), store_(store), feed_(feed), queue_(options.queue_capacity) {}

void QueuedMergeWorker::StartThread() {
  last_publish_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this] { Run(); });
}

void QueuedMergeWorker::Stop() {
  if (!thread_.joinable()) return;
  stopping_ = true;
  queue_.Close();
  thread_.join();
}

void QueuedMergeWorker::Submit(MergeEvent event) {
  if (!queue_.TryPush(std::move(event))) resync_needed_ = true;
}

std::vector<RobotPlacementRecord> QueuedMergeWorker::Placements() const {
  std::lock_guard<std::mutex> lock(placements_mutex_);
  return placements_;
}

void QueuedMergeWorker::SetPlacements(std::vector<RobotPlacementRecord> placements) {
  std::lock_guard<std::mutex> lock(placements_mutex_);
  placements_ = std::move(placements);
}

bool QueuedMergeWorker::PublishStoredVersion(const VersionRecord& version) {
  auto snapshot = std::make_shared<GlobalMapSnapshot>();
  snapshot->info = version;
  const auto grid = store_->GetVersionGrid(version.version);
  GridDecodeError code;
  std::string error;
  if (!grid || !Decompress(*grid, GridLimits(), &snapshot->grid, &code, &error)) return false;
  snapshot->encoded = *grid;
  feed_->Publish(snapshot);
  return true;
}

VersionRecord QueuedMergeWorker::PendingVersion(const std::string& default_trigger,
                                                const std::string& engine) const {
  VersionRecord info;
  info.created_unix_time =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  info.covered_submap_seq = covered_seq_;
  info.trigger = trigger_.empty() ? default_trigger : trigger_;
  info.trigger_robot_ids.assign(trigger_robots_.begin(), trigger_robots_.end());
  info.new_submaps = new_submaps_;
  info.new_detections = new_detections_;
  info.merge_engine = engine;
  info.placements = Placements();
  int placed = 0;
  for (const auto& p : info.placements) placed += p.placed;
  info.quality["robots_placed"] = placed;
  info.quality["robots_unplaced"] = static_cast<double>(info.placements.size()) - placed;
  return info;
}

bool QueuedMergeWorker::StoreAndPublish(VersionRecord info, const OccupancyGrid& canvas) {
  auto snapshot = std::make_shared<GlobalMapSnapshot>();
  snapshot->grid = Quantize(canvas, common_options_.log_odds_limit, /*crop_to_known=*/true);
  if (snapshot->grid.geometry.cells() == 0) snapshot->grid.geometry.origin.setZero();
  snapshot->encoded = Compress(snapshot->grid, common_options_.zstd_level);
  std::string error;
  info.version = store_->PutVersion(info, snapshot->encoded, &error);
  last_publish_ = std::chrono::steady_clock::now();
  if (info.version == 0) {
    // Keep the pending provenance; the next pass retries.
    std::cerr << "fleetmap-server: storing a global map version failed: " << error << "\n";
    return false;
  }
  info.geometry = snapshot->encoded.geometry;
  info.grid_available = true;
  snapshot->info = std::move(info);
  feed_->Publish(snapshot);
  dirty_ = false;
  trigger_.clear();
  trigger_robots_.clear();
  new_submaps_.clear();
  new_detections_.clear();
  return true;
}

}  // namespace fleetmap
