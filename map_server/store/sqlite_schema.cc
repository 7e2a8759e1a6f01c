#include "map_server/store/sqlite_schema.h"

#include <sqlite3.h>

#include <vector>

#include "map_server/store/sqlite_db.h"

namespace fleetmap {
namespace {

// kMigrations[i] takes the schema from version i to i + 1. Never edit a shipped migration;
// append a new one.
const std::vector<std::string>& Migrations() {
  static const std::vector<std::string> migrations = {
      // 0 -> 1: the first schema.
      R"sql(
CREATE TABLE schema_version (version INTEGER NOT NULL);
INSERT INTO schema_version (version) VALUES (0);
CREATE TABLE robots (
  robot_id TEXT PRIMARY KEY, name TEXT NOT NULL, sensor TEXT NOT NULL, algorithm TEXT NOT NULL,
  registered_time REAL NOT NULL, has_pose INTEGER NOT NULL,
  pose_x REAL NOT NULL, pose_y REAL NOT NULL, pose_theta REAL NOT NULL);
CREATE TABLE submaps (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  robot_id TEXT NOT NULL REFERENCES robots(robot_id), submap_id INTEGER NOT NULL,
  revision INTEGER NOT NULL, received_time REAL NOT NULL,
  anchor_x REAL NOT NULL, anchor_y REAL NOT NULL, anchor_theta REAL NOT NULL,
  finished INTEGER NOT NULL, scan_poses BLOB NOT NULL,
  grid_width INTEGER NOT NULL, grid_height INTEGER NOT NULL, grid_resolution REAL NOT NULL,
  grid_origin_x REAL NOT NULL, grid_origin_y REAL NOT NULL, grid_scale REAL NOT NULL,
  grid_cells BLOB NOT NULL,
  UNIQUE (robot_id, submap_id, revision));
CREATE TABLE trajectories (
  robot_id TEXT NOT NULL REFERENCES robots(robot_id), revision INTEGER NOT NULL,
  received_time REAL NOT NULL, poses BLOB NOT NULL,
  PRIMARY KEY (robot_id, revision));
CREATE TABLE detections (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  observer_id TEXT NOT NULL REFERENCES robots(robot_id), detection_id INTEGER NOT NULL,
  observed_id TEXT NOT NULL, timestamp REAL NOT NULL, x REAL NOT NULL, y REAL NOT NULL,
  cov_xx REAL NOT NULL, cov_xy REAL NOT NULL, cov_yy REAL NOT NULL,
  has_heading INTEGER NOT NULL, heading REAL NOT NULL, heading_variance REAL NOT NULL,
  confidence REAL NOT NULL, received_time REAL NOT NULL,
  UNIQUE (observer_id, detection_id));
CREATE TABLE versions (
  version INTEGER PRIMARY KEY, created_time REAL NOT NULL, covered_submap_seq INTEGER NOT NULL,
  trigger TEXT NOT NULL, merge_engine TEXT NOT NULL,
  grid_width INTEGER NOT NULL, grid_height INTEGER NOT NULL, grid_resolution REAL NOT NULL,
  grid_origin_x REAL NOT NULL, grid_origin_y REAL NOT NULL, grid_scale REAL NOT NULL,
  grid_cells BLOB);
CREATE INDEX versions_by_time ON versions (created_time);
CREATE TABLE version_trigger_robots (version INTEGER NOT NULL, robot_id TEXT NOT NULL);
CREATE INDEX version_trigger_robots_by_version ON version_trigger_robots (version);
CREATE TABLE version_submaps (
  version INTEGER NOT NULL, robot_id TEXT NOT NULL, submap_id INTEGER NOT NULL,
  revision INTEGER NOT NULL);
CREATE INDEX version_submaps_by_version ON version_submaps (version);
CREATE TABLE version_detections (
  version INTEGER NOT NULL, observer_id TEXT NOT NULL, detection_id INTEGER NOT NULL);
CREATE INDEX version_detections_by_version ON version_detections (version);
CREATE TABLE version_quality (version INTEGER NOT NULL, name TEXT NOT NULL, value REAL NOT NULL);
CREATE INDEX version_quality_by_version ON version_quality (version);
-- Where each robot's local frame sat in the global frame, per version.
CREATE TABLE alignments (
  version INTEGER NOT NULL, robot_id TEXT NOT NULL, placed INTEGER NOT NULL,
  x REAL NOT NULL, y REAL NOT NULL, theta REAL NOT NULL, source TEXT NOT NULL,
  note TEXT NOT NULL);
CREATE INDEX alignments_by_version ON alignments (version);
)sql",
      // 1 -> 2: where each robot's first submap places its local frame (NULL: not recorded).
      R"sql(
ALTER TABLE alignments ADD COLUMN start_x REAL;
ALTER TABLE alignments ADD COLUMN start_y REAL;
ALTER TABLE alignments ADD COLUMN start_theta REAL;
)sql",
      // 2 -> 3: robots that localize in a known map instead of mapping.
      R"sql(
ALTER TABLE robots ADD COLUMN localization_only INTEGER NOT NULL DEFAULT 0;
)sql",
  };
  return migrations;
}

bool TableExists(sqlite3* db, const std::string& name) {
  SqliteStatement query(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
  query.Bind(1, name);
  return query.Step();
}

}  // namespace

int ReadSchemaVersion(sqlite3* db, std::string* error) {
  if (!TableExists(db, "schema_version")) {
    SqliteStatement tables(db, "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table'");
    if (!tables.Step()) {
      *error = "cannot read the database: " + tables.error();
      return -1;
    }
    if (tables.Int(0) > 0) {
      *error = "the database has tables but no schema_version table: not a fleetmap database";
      return -1;
    }
    return 0;
  }
  SqliteStatement query(db, "SELECT MAX(version) FROM schema_version");
  if (!query.Step() || query.IsNull(0)) {
    *error = "the schema_version table is empty or unreadable";
    return -1;
  }
  return static_cast<int>(query.Int(0));
}

bool MigrateSchema(sqlite3* db, std::string* error) {
  const int current = ReadSchemaVersion(db, error);
  if (current < 0) return false;
  if (current > kSqliteSchemaVersion) {
    *error = "the database has schema version " + std::to_string(current) +
             ", newer than this server understands (" + std::to_string(kSqliteSchemaVersion) +
             "); run a newer fleetmap-server or restore a backup";
    return false;
  }
  const auto& migrations = Migrations();
  for (int version = current; version < kSqliteSchemaVersion; ++version) {
    SqliteTransaction transaction(db);
    if (!transaction.ok()) {
      *error = "cannot start migration: " + transaction.error();
      return false;
    }
    std::string step_error;
    if (!SqliteExec(db, migrations[static_cast<size_t>(version)], &step_error) ||
        !SqliteExec(db,
                    "UPDATE schema_version SET version = " + std::to_string(version + 1),
                    &step_error) ||
        !transaction.Commit(&step_error)) {
      *error = "migration to schema version " + std::to_string(version + 1) +
               " failed: " + step_error;
      return false;
    }
  }
  return true;
}

}  // namespace fleetmap
