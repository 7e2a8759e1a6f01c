#ifndef FLEETMAP_MAP_SERVER_STORE_MEMORY_MAP_STORE_H_
#define FLEETMAP_MAP_SERVER_STORE_MEMORY_MAP_STORE_H_

#include <map>
#include <mutex>
#include <utility>

#include "map_server/store/map_store.h"

namespace fleetmap {

// A MapStore in memory, with the same semantics as the SQLite one; for tests.
class MemoryMapStore : public MapStore {
 public:
  explicit MemoryMapStore(const RetentionOptions& retention = RetentionOptions())
      : retention_(retention) {}

  bool PutRobot(const RobotRecord& robot, bool* existed, std::string* error) override;
  std::optional<RobotRecord> GetRobot(const std::string& robot_id) override;
  std::vector<RobotRecord> ListRobots() override;

  PutOutcome PutSubmap(const Submap& submap, double received_unix_time, int64_t* seq,
                       std::string* error) override;
  std::optional<StoredSubmap> GetSubmap(const SubmapKey& key) override;
  std::vector<StoredSubmap> LatestSubmaps(const std::string& robot_id) override;
  int64_t CountSubmapRevisions(const std::string& robot_id) override;
  int64_t CountSubmapIds(const std::string& robot_id) override;
  int64_t MaxSubmapSeq() override;

  PutOutcome PutTrajectory(const TrajectoryRecord& trajectory, std::string* error) override;
  std::optional<TrajectoryRecord> LatestTrajectory(const std::string& robot_id) override;

  PutOutcome PutDetection(const DetectionRecord& detection, int64_t* seq,
                          std::string* error) override;
  std::vector<DetectionRecord> DetectionsAfter(int64_t seq) override;

  int64_t PutVersion(const VersionRecord& version, const EncodedGrid& grid,
                     std::string* error) override;
  std::optional<VersionRecord> GetVersion(int64_t version) override;
  std::optional<VersionRecord> LatestVersion() override;
  std::optional<VersionRecord> VersionAtTime(double unix_time) override;
  std::vector<VersionRecord> ListVersions(int limit, int64_t before_version) override;
  std::optional<EncodedGrid> GetVersionGrid(int64_t version) override;

 private:
  const RetentionOptions retention_;
  std::mutex mutex_;  // guards everything below
  std::map<std::string, RobotRecord> robots_;
  std::map<SubmapKey, StoredSubmap> submaps_;
  int64_t next_submap_seq_ = 1;
  std::map<std::pair<std::string, int64_t>, TrajectoryRecord> trajectories_;
  std::map<std::pair<std::string, int64_t>, DetectionRecord> detections_;
  int64_t next_detection_seq_ = 1;
  std::map<int64_t, VersionRecord> versions_;
  std::map<int64_t, EncodedGrid> version_grids_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_MEMORY_MAP_STORE_H_
