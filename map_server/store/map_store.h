#ifndef FLEETMAP_MAP_SERVER_STORE_MAP_STORE_H_
#define FLEETMAP_MAP_SERVER_STORE_MAP_STORE_H_

#include <optional>
#include <string>
#include <vector>

#include "map_server/store/records.h"

namespace fleetmap {

// Durable storage of everything the server has accepted. Each Put is one transaction: when it
// returns kInserted or kDuplicate the item is committed and may be acknowledged.
// Implementations are thread-safe.
class MapStore {
 public:
  virtual ~MapStore() = default;

  // Inserts or updates a robot; sets `*existed` when it was registered before.
  virtual bool PutRobot(const RobotRecord& robot, bool* existed, std::string* error) = 0;
  virtual std::optional<RobotRecord> GetRobot(const std::string& robot_id) = 0;
  virtual std::vector<RobotRecord> ListRobots() = 0;

  // Idempotent by (robot_id, submap_id, revision); `*seq` gets the stored row's ingest order.
  virtual PutOutcome PutSubmap(const Submap& submap, double received_unix_time, int64_t* seq,
                               std::string* error) = 0;
  virtual std::optional<StoredSubmap> GetSubmap(const SubmapKey& key) = 0;
  // The newest revision of every submap (of one robot, or all when `robot_id` is empty).
  virtual std::vector<StoredSubmap> LatestSubmaps(const std::string& robot_id) = 0;
  virtual int64_t CountSubmapRevisions(const std::string& robot_id) = 0;
  virtual int64_t CountSubmapIds(const std::string& robot_id) = 0;
  virtual int64_t MaxSubmapSeq() = 0;

  // Idempotent by (robot_id, revision).
  virtual PutOutcome PutTrajectory(const TrajectoryRecord& trajectory, std::string* error) = 0;
  virtual std::optional<TrajectoryRecord> LatestTrajectory(const std::string& robot_id) = 0;

  // Idempotent by (observer_id, detection_id). Only the observer must be registered.
  virtual PutOutcome PutDetection(const DetectionRecord& detection, int64_t* seq,
                                  std::string* error) = 0;
  virtual std::vector<DetectionRecord> DetectionsAfter(int64_t seq) = 0;

  // Stores a version (its number is assigned: previous + 1) with its grid; then applies the
  // retention setting. Returns the version number, or 0 with `error`.
  virtual int64_t PutVersion(const VersionRecord& version, const EncodedGrid& grid,
                             std::string* error) = 0;
  virtual std::optional<VersionRecord> GetVersion(int64_t version) = 0;
  virtual std::optional<VersionRecord> LatestVersion() = 0;
  // The newest version created at or before `unix_time`.
  virtual std::optional<VersionRecord> VersionAtTime(double unix_time) = 0;
  // Newest first; `before_version` > 0 restricts to older versions.
  virtual std::vector<VersionRecord> ListVersions(int limit, int64_t before_version) = 0;
  // Empty when unknown or pruned by retention.
  virtual std::optional<EncodedGrid> GetVersionGrid(int64_t version) = 0;
};

// How many versions keep their grid (older ones keep only metadata); 0 keeps all.
struct RetentionOptions {
  int keep_version_grids = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_MAP_STORE_H_
