#include "map_server/store/memory_map_store.h"

#include <cstdint>
#include <iterator>
#include <set>

namespace fleetmap {

bool MemoryMapStore::PutRobot(const RobotRecord& robot, bool* existed, std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = robots_.find(robot.robot_id);
  *existed = it != robots_.end();
  RobotRecord stored = robot;
  if (*existed) stored.registered_unix_time = it->second.registered_unix_time;
  robots_[robot.robot_id] = stored;
  return true;
}

std::optional<RobotRecord> MemoryMapStore::GetRobot(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return std::nullopt;
  return it->second;
}

std::vector<RobotRecord> MemoryMapStore::ListRobots() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<RobotRecord> out;
  for (const auto& [id, robot] : robots_) out.push_back(robot);
  return out;
}

PutOutcome MemoryMapStore::PutSubmap(const Submap& submap, double received_unix_time,
                                     int64_t* seq, std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!robots_.count(submap.robot_id)) return PutOutcome::kUnknownRobot;
  const SubmapKey key{submap.robot_id, submap.submap_id, submap.revision};
  auto exact = submaps_.find(key);
  if (exact != submaps_.end()) {
    *seq = exact->second.seq;
    return PutOutcome::kDuplicate;
  }
  // The newest stored revision of this submap is the last key before (id + 1, revision 0).
  auto next = submaps_.lower_bound(SubmapKey{submap.robot_id, submap.submap_id + 1, INT64_MIN});
  if (next != submaps_.begin()) {
    const SubmapKey& newest = std::prev(next)->first;
    if (newest.robot_id == key.robot_id && newest.submap_id == key.submap_id &&
        newest.revision > key.revision) {
      return PutOutcome::kOutOfOrder;
    }
  }
  StoredSubmap stored{next_submap_seq_++, received_unix_time, submap};
  *seq = stored.seq;
  submaps_.emplace(key, std::move(stored));
  return PutOutcome::kInserted;
}

std::optional<StoredSubmap> MemoryMapStore::GetSubmap(const SubmapKey& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = submaps_.find(key);
  if (it == submaps_.end()) return std::nullopt;
  return it->second;
}

std::vector<StoredSubmap> MemoryMapStore::LatestSubmaps(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<StoredSubmap> out;
  for (auto it = submaps_.begin(); it != submaps_.end(); ++it) {
    auto next = std::next(it);
    const bool last_revision = next == submaps_.end() ||
                               next->first.robot_id != it->first.robot_id ||
                               next->first.submap_id != it->first.submap_id;
    if (last_revision && (robot_id.empty() || robot_id == it->first.robot_id)) {
      out.push_back(it->second);
    }
  }
  return out;
}

int64_t MemoryMapStore::CountSubmapRevisions(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  int64_t n = 0;
  for (const auto& [key, s] : submaps_) n += (robot_id.empty() || key.robot_id == robot_id);
  return n;
}

int64_t MemoryMapStore::CountSubmapIds(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::set<std::pair<std::string, int64_t>> ids;
  for (const auto& [key, s] : submaps_) {
    if (robot_id.empty() || key.robot_id == robot_id) ids.insert({key.robot_id, key.submap_id});
  }
  return static_cast<int64_t>(ids.size());
}

int64_t MemoryMapStore::MaxSubmapSeq() {
  std::lock_guard<std::mutex> lock(mutex_);
  return next_submap_seq_ - 1;
}

PutOutcome MemoryMapStore::PutTrajectory(const TrajectoryRecord& trajectory,
                                         std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!robots_.count(trajectory.robot_id)) return PutOutcome::kUnknownRobot;
  const auto key = std::make_pair(trajectory.robot_id, trajectory.revision);
  if (trajectories_.count(key)) return PutOutcome::kDuplicate;
  auto next = trajectories_.lower_bound({trajectory.robot_id, INT64_MAX});
  if (next != trajectories_.begin() && std::prev(next)->first.first == trajectory.robot_id &&
      std::prev(next)->first.second > trajectory.revision) {
    return PutOutcome::kOutOfOrder;
  }
  trajectories_[key] = trajectory;
  return PutOutcome::kInserted;
}

std::optional<TrajectoryRecord> MemoryMapStore::LatestTrajectory(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto next = trajectories_.lower_bound({robot_id, INT64_MAX});
  if (next == trajectories_.begin() || std::prev(next)->first.first != robot_id) {
    return std::nullopt;
  }
  return std::prev(next)->second;
}

PutOutcome MemoryMapStore::PutDetection(const DetectionRecord& detection, int64_t* seq,
                                        std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!robots_.count(detection.detection.observer_id)) return PutOutcome::kUnknownRobot;
  const auto key = std::make_pair(detection.detection.observer_id, detection.detection_id);
  auto it = detections_.find(key);
  if (it != detections_.end()) {
    *seq = it->second.seq;
    return PutOutcome::kDuplicate;
  }
  DetectionRecord stored = detection;
  stored.seq = next_detection_seq_++;
  *seq = stored.seq;
  detections_[key] = stored;
  return PutOutcome::kInserted;
}

std::vector<DetectionRecord> MemoryMapStore::DetectionsAfter(int64_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<int64_t, DetectionRecord> by_seq;
  for (const auto& [key, d] : detections_) {
    if (d.seq > seq) by_seq[d.seq] = d;
  }
  std::vector<DetectionRecord> out;
  for (auto& [s, d] : by_seq) out.push_back(std::move(d));
  return out;
}

int64_t MemoryMapStore::PutVersion(const VersionRecord& version, const EncodedGrid& grid,
                                   std::string* /*error*/) {
  std::lock_guard<std::mutex> lock(mutex_);
  VersionRecord stored = version;
  stored.version = versions_.empty() ? 1 : versions_.rbegin()->first + 1;
  stored.geometry = grid.geometry;
  stored.grid_available = true;
  versions_[stored.version] = stored;
  version_grids_[stored.version] = grid;
  if (retention_.keep_version_grids > 0) {
    while (static_cast<int>(version_grids_.size()) > retention_.keep_version_grids) {
      versions_[version_grids_.begin()->first].grid_available = false;
      version_grids_.erase(version_grids_.begin());
    }
  }
  return stored.version;
}

std::optional<VersionRecord> MemoryMapStore::GetVersion(int64_t version) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = versions_.find(version);
  if (it == versions_.end()) return std::nullopt;
  return it->second;
}

std::optional<VersionRecord> MemoryMapStore::LatestVersion() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (versions_.empty()) return std::nullopt;
  return versions_.rbegin()->second;
}

std::optional<VersionRecord> MemoryMapStore::VersionAtTime(double unix_time) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = versions_.rbegin(); it != versions_.rend(); ++it) {
    if (it->second.created_unix_time <= unix_time) return it->second;
  }
  return std::nullopt;
}

std::vector<VersionRecord> MemoryMapStore::ListVersions(int limit, int64_t before_version) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<VersionRecord> out;
  for (auto it = versions_.rbegin(); it != versions_.rend() && static_cast<int>(out.size()) < limit;
       ++it) {
    if (before_version <= 0 || it->first < before_version) out.push_back(it->second);
  }
  return out;
}

std::optional<EncodedGrid> MemoryMapStore::GetVersionGrid(int64_t version) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = version_grids_.find(version);
  if (it == version_grids_.end()) return std::nullopt;
  return it->second;
}

}  // namespace fleetmap
