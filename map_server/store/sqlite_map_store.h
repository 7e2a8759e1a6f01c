#ifndef FLEETMAP_MAP_SERVER_STORE_SQLITE_MAP_STORE_H_
#define FLEETMAP_MAP_SERVER_STORE_SQLITE_MAP_STORE_H_

#include <memory>
#include <mutex>

#include "map_server/store/map_store.h"

struct sqlite3;

namespace fleetmap {

struct SqliteMapStoreOptions {
  std::string path;  // database file, created when missing
  // true: fsync on every commit (survives power loss). false: WAL with synchronous=NORMAL,
  // which survives a killed process (SIGKILL) but may lose the last commits on power loss.
  bool fsync_every_commit = false;
  RetentionOptions retention;
};

// The production MapStore: one SQLite database in WAL mode, one connection guarded by a mutex,
// one transaction per Put.
class SqliteMapStore : public MapStore {
 public:
  // Opens (creating and migrating when needed); nullptr with `error` on failure, including a
  // database written by a newer server.
  static std::unique_ptr<SqliteMapStore> Open(const SqliteMapStoreOptions& options,
                                              std::string* error);
  ~SqliteMapStore() override;

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
  SqliteMapStore(sqlite3* db, const SqliteMapStoreOptions& options)
      : db_(db), options_(options) {}
  bool RobotExists(const std::string& robot_id);
  // Fills the provenance tables of a version read from the versions table (mutex held).
  void LoadProvenance(VersionRecord* version);
  std::vector<VersionRecord> QueryVersions(const std::string& where_and_order, double arg);

  sqlite3* db_;
  const SqliteMapStoreOptions options_;
  std::mutex mutex_;  // one connection: every statement runs under this lock
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_SQLITE_MAP_STORE_H_
