#include "map_server/store/sqlite_map_store.h"

#include <sqlite3.h>

#include "map_server/store/pose_blob.h"
#include "map_server/store/sqlite_db.h"
#include "map_server/store/sqlite_schema.h"

namespace fleetmap {
namespace {

constexpr char kSubmapColumns[] =
    "seq, robot_id, submap_id, revision, received_time, anchor_x, anchor_y, anchor_theta, "
    "finished, scan_poses, grid_width, grid_height, grid_resolution, grid_origin_x, "
    "grid_origin_y, grid_scale, grid_cells";

// Rows were validated on the way in; a row that no longer decodes (disk corruption) is skipped.
std::optional<StoredSubmap> SubmapFromRow(const SqliteStatement& row) {
  StoredSubmap out;
  out.seq = row.Int(0);
  out.submap.robot_id = row.Text(1);
  out.submap.submap_id = row.Int(2);
  out.submap.revision = row.Int(3);
  out.received_unix_time = row.Double(4);
  out.submap.submap_in_local = Rigid2d(row.Double(5), row.Double(6), row.Double(7));
  out.submap.finished = row.Int(8) != 0;
  if (!UnpackPoses(row.Blob(9), &out.submap.scan_poses)) return std::nullopt;
  EncodedGrid encoded;
  encoded.geometry.width = static_cast<int>(row.Int(10));
  encoded.geometry.height = static_cast<int>(row.Int(11));
  encoded.geometry.resolution = row.Double(12);
  encoded.geometry.origin = Eigen::Vector2d(row.Double(13), row.Double(14));
  encoded.log_odds_scale = static_cast<float>(row.Double(15));
  encoded.compressed = row.Blob(16);
  GridDecodeError code;
  std::string error;
  if (!DecodeGrid(encoded, GridLimits(), OccupancyGridOptions(), &out.submap.grid, &code,
                  &error)) {
    return std::nullopt;
  }
  return out;
}

RobotRecord RobotFromRow(const SqliteStatement& row) {
  RobotRecord robot;
  robot.robot_id = row.Text(0);
  robot.name = row.Text(1);
  robot.sensor_description = row.Text(2);
  robot.algorithm = row.Text(3);
  robot.registered_unix_time = row.Double(4);
  if (row.Int(5) != 0) robot.local_in_global = Rigid2d(row.Double(6), row.Double(7), row.Double(8));
  robot.localization_only = row.Int(9) != 0;
  return robot;
}

}  // namespace

std::unique_ptr<SqliteMapStore> SqliteMapStore::Open(const SqliteMapStoreOptions& options,
                                                     std::string* error) {
  sqlite3* db = nullptr;
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX;
  if (sqlite3_open_v2(options.path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    *error = "cannot open database " + options.path + ": " +
             (db ? sqlite3_errmsg(db) : "out of memory");
    sqlite3_close(db);
    return nullptr;
  }
  std::unique_ptr<SqliteMapStore> store(new SqliteMapStore(db, options));
  sqlite3_busy_timeout(db, 5000);
  std::string step_error;
  SqliteStatement wal(db, "PRAGMA journal_mode = WAL");
  if (!wal.Step() || wal.Text(0) != "wal") {
    *error = "cannot switch " + options.path + " to WAL mode: " + wal.error();
    return nullptr;
  }
  const std::string sync = options.fsync_every_commit ? "FULL" : "NORMAL";
  if (!SqliteExec(db, "PRAGMA synchronous = " + sync + "; PRAGMA foreign_keys = ON", &step_error) ||
      !MigrateSchema(db, &step_error)) {
    *error = options.path + ": " + step_error;
    return nullptr;
  }
  return store;
}

SqliteMapStore::~SqliteMapStore() { sqlite3_close(db_); }

bool SqliteMapStore::RobotExists(const std::string& robot_id) {
  SqliteStatement query(db_, "SELECT 1 FROM robots WHERE robot_id = ?");
  query.Bind(1, robot_id);
  return query.Step();
}

bool SqliteMapStore::PutRobot(const RobotRecord& robot, bool* existed, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteTransaction transaction(db_);
  *existed = RobotExists(robot.robot_id);
  const Rigid2d pose = robot.local_in_global.value_or(Rigid2d());
  SqliteStatement upsert(
      db_,
      "INSERT INTO robots (robot_id, name, sensor, algorithm, registered_time, has_pose, pose_x, "
      "pose_y, pose_theta, localization_only) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
      "ON CONFLICT (robot_id) DO UPDATE "
      "SET name = excluded.name, sensor = excluded.sensor, algorithm = excluded.algorithm, "
      "has_pose = excluded.has_pose, pose_x = excluded.pose_x, pose_y = excluded.pose_y, "
      "pose_theta = excluded.pose_theta, localization_only = excluded.localization_only");
  upsert.Bind(1, robot.robot_id).Bind(2, robot.name).Bind(3, robot.sensor_description);
  upsert.Bind(4, robot.algorithm).Bind(5, robot.registered_unix_time);
  upsert.Bind(6, static_cast<int64_t>(robot.local_in_global.has_value()));
  upsert.Bind(7, pose.x()).Bind(8, pose.y()).Bind(9, pose.rotation());
  upsert.Bind(10, static_cast<int64_t>(robot.localization_only));
  if (!upsert.Run()) {
    *error = "storing robot: " + upsert.error();
    return false;
  }
  return transaction.Commit(error);
}

std::optional<RobotRecord> SqliteMapStore::GetRobot(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(
      db_,
      "SELECT robot_id, name, sensor, algorithm, registered_time, has_pose, "
      "pose_x, pose_y, pose_theta, localization_only FROM robots WHERE robot_id = ?");
  query.Bind(1, robot_id);
  if (!query.Step()) return std::nullopt;
  return RobotFromRow(query);
}

std::vector<RobotRecord> SqliteMapStore::ListRobots() {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(
      db_,
      "SELECT robot_id, name, sensor, algorithm, registered_time, has_pose, "
      "pose_x, pose_y, pose_theta, localization_only FROM robots ORDER BY robot_id");
  std::vector<RobotRecord> out;
  while (query.Step()) out.push_back(RobotFromRow(query));
  return out;
}

PutOutcome SqliteMapStore::PutSubmap(const Submap& submap, double received_unix_time,
                                     int64_t* seq, std::string* error) {
  // Encoding happens outside the lock: it is the only CPU-heavy part of a put.
  const EncodedGrid grid = EncodeGrid(submap.grid);
  const std::string poses = PackPoses(submap.scan_poses);
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteTransaction transaction(db_);
  if (!transaction.ok()) {
    *error = transaction.error();
    return PutOutcome::kError;
  }
  if (!RobotExists(submap.robot_id)) return PutOutcome::kUnknownRobot;
  SqliteStatement existing(db_,
                           "SELECT seq FROM submaps WHERE robot_id = ? AND submap_id = ? AND "
                           "revision = ?");
  existing.Bind(1, submap.robot_id).Bind(2, submap.submap_id).Bind(3, submap.revision);
  if (existing.Step()) {
    *seq = existing.Int(0);
    return PutOutcome::kDuplicate;
  }
  SqliteStatement newest(db_,
                         "SELECT MAX(revision) FROM submaps WHERE robot_id = ? AND submap_id = ?");
  newest.Bind(1, submap.robot_id).Bind(2, submap.submap_id);
  if (newest.Step() && !newest.IsNull(0) && newest.Int(0) > submap.revision) {
    return PutOutcome::kOutOfOrder;
  }
  SqliteStatement insert(db_, std::string("INSERT INTO submaps (") + kSubmapColumns +
                                  ") VALUES (NULL, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  insert.Bind(1, submap.robot_id).Bind(2, submap.submap_id).Bind(3, submap.revision);
  insert.Bind(4, received_unix_time);
  insert.Bind(5, submap.submap_in_local.x()).Bind(6, submap.submap_in_local.y());
  insert.Bind(7, submap.submap_in_local.rotation());
  insert.Bind(8, static_cast<int64_t>(submap.finished)).BindBlob(9, poses);
  insert.Bind(10, static_cast<int64_t>(grid.geometry.width));
  insert.Bind(11, static_cast<int64_t>(grid.geometry.height));
  insert.Bind(12, grid.geometry.resolution).Bind(13, grid.geometry.origin.x());
  insert.Bind(14, grid.geometry.origin.y()).Bind(15, static_cast<double>(grid.log_odds_scale));
  insert.BindBlob(16, grid.compressed);
  if (!insert.Run()) {
    *error = "storing submap: " + insert.error();
    return PutOutcome::kError;
  }
  *seq = sqlite3_last_insert_rowid(db_);
  if (!transaction.Commit(error)) return PutOutcome::kError;
  return PutOutcome::kInserted;
}

std::optional<StoredSubmap> SqliteMapStore::GetSubmap(const SubmapKey& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_, std::string("SELECT ") + kSubmapColumns +
                                 " FROM submaps WHERE robot_id = ? AND submap_id = ? AND "
                                 "revision = ?");
  query.Bind(1, key.robot_id).Bind(2, key.submap_id).Bind(3, key.revision);
  if (!query.Step()) return std::nullopt;
  return SubmapFromRow(query);
}

std::vector<StoredSubmap> SqliteMapStore::LatestSubmaps(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The newest revision of each submap id; the UNIQUE index makes the inner MAX a lookup.
  SqliteStatement query(
      db_, std::string("SELECT ") + kSubmapColumns +
               " FROM submaps s WHERE (?1 = '' OR robot_id = ?1) AND revision = (SELECT "
               "MAX(revision) FROM submaps WHERE robot_id = s.robot_id AND submap_id = "
               "s.submap_id) ORDER BY seq");
  query.Bind(1, robot_id);
  std::vector<StoredSubmap> out;
  while (query.Step()) {
    auto submap = SubmapFromRow(query);
    if (submap) out.push_back(std::move(*submap));
  }
  return out;
}

int64_t SqliteMapStore::CountSubmapRevisions(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_, "SELECT COUNT(*) FROM submaps WHERE ?1 = '' OR robot_id = ?1");
  query.Bind(1, robot_id);
  return query.Step() ? query.Int(0) : 0;
}

int64_t SqliteMapStore::CountSubmapIds(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_,
                        "SELECT COUNT(*) FROM (SELECT DISTINCT robot_id, submap_id FROM submaps "
                        "WHERE ?1 = '' OR robot_id = ?1)");
  query.Bind(1, robot_id);
  return query.Step() ? query.Int(0) : 0;
}

int64_t SqliteMapStore::MaxSubmapSeq() {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_, "SELECT COALESCE(MAX(seq), 0) FROM submaps");
  return query.Step() ? query.Int(0) : 0;
}

}  // namespace fleetmap
