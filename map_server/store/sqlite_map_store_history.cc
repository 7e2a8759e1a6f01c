// SqliteMapStore: trajectories, detections and global map versions.
#include <sqlite3.h>

#include "map_server/store/pose_blob.h"
#include "map_server/store/sqlite_db.h"
#include "map_server/store/sqlite_map_store.h"

namespace fleetmap {
namespace {

constexpr char kVersionColumns[] =
    "version, created_time, covered_submap_seq, trigger, merge_engine, grid_width, grid_height, "
    "grid_resolution, grid_origin_x, grid_origin_y, grid_scale, grid_cells IS NOT NULL";

VersionRecord VersionFromRow(const SqliteStatement& row) {
  VersionRecord v;
  v.version = row.Int(0);
  v.created_unix_time = row.Double(1);
  v.covered_submap_seq = row.Int(2);
  v.trigger = row.Text(3);
  v.merge_engine = row.Text(4);
  v.geometry.width = static_cast<int>(row.Int(5));
  v.geometry.height = static_cast<int>(row.Int(6));
  v.geometry.resolution = row.Double(7);
  v.geometry.origin = Eigen::Vector2d(row.Double(8), row.Double(9));
  v.grid_available = row.Int(11) != 0;
  return v;
}

bool RunOrFail(SqliteStatement* statement, std::string* error) {
  if (statement->Run()) return true;
  *error = statement->error();
  return false;
}

}  // namespace

PutOutcome SqliteMapStore::PutTrajectory(const TrajectoryRecord& trajectory, std::string* error) {
  const std::string poses = PackPoses(trajectory.poses);
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteTransaction transaction(db_);
  if (!RobotExists(trajectory.robot_id)) return PutOutcome::kUnknownRobot;
  SqliteStatement newest(db_, "SELECT MAX(revision) FROM trajectories WHERE robot_id = ?");
  newest.Bind(1, trajectory.robot_id);
  if (newest.Step() && !newest.IsNull(0)) {
    SqliteStatement exact(db_, "SELECT 1 FROM trajectories WHERE robot_id = ? AND revision = ?");
    exact.Bind(1, trajectory.robot_id).Bind(2, trajectory.revision);
    if (exact.Step()) return PutOutcome::kDuplicate;
    if (newest.Int(0) > trajectory.revision) return PutOutcome::kOutOfOrder;
  }
  SqliteStatement insert(db_,
                         "INSERT INTO trajectories (robot_id, revision, received_time, poses) "
                         "VALUES (?, ?, ?, ?)");
  insert.Bind(1, trajectory.robot_id).Bind(2, trajectory.revision);
  insert.Bind(3, trajectory.received_unix_time).BindBlob(4, poses);
  if (!RunOrFail(&insert, error) || !transaction.Commit(error)) return PutOutcome::kError;
  return PutOutcome::kInserted;
}

std::optional<TrajectoryRecord> SqliteMapStore::LatestTrajectory(const std::string& robot_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_,
                        "SELECT revision, received_time, poses FROM trajectories WHERE robot_id "
                        "= ? ORDER BY revision DESC LIMIT 1");
  query.Bind(1, robot_id);
  if (!query.Step()) return std::nullopt;
  TrajectoryRecord out;
  out.robot_id = robot_id;
  out.revision = query.Int(0);
  out.received_unix_time = query.Double(1);
  if (!UnpackPoses(query.Blob(2), &out.poses)) return std::nullopt;
  return out;
}

PutOutcome SqliteMapStore::PutDetection(const DetectionRecord& record, int64_t* seq,
                                        std::string* error) {
  const RobotDetection& d = record.detection;
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteTransaction transaction(db_);
  if (!RobotExists(d.observer_id)) return PutOutcome::kUnknownRobot;
  SqliteStatement existing(db_,
                           "SELECT seq FROM detections WHERE observer_id = ? AND detection_id = ?");
  existing.Bind(1, d.observer_id).Bind(2, record.detection_id);
  if (existing.Step()) {
    *seq = existing.Int(0);
    return PutOutcome::kDuplicate;
  }
  SqliteStatement insert(
      db_,
      "INSERT INTO detections (observer_id, detection_id, observed_id, timestamp, x, y, cov_xx, "
      "cov_xy, cov_yy, has_heading, heading, heading_variance, confidence, received_time) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  insert.Bind(1, d.observer_id).Bind(2, record.detection_id).Bind(3, d.observed_id);
  insert.Bind(4, d.timestamp).Bind(5, d.position_in_observer.x());
  insert.Bind(6, d.position_in_observer.y()).Bind(7, d.covariance(0, 0));
  insert.Bind(8, d.covariance(0, 1)).Bind(9, d.covariance(1, 1));
  insert.Bind(10, static_cast<int64_t>(d.relative_heading.has_value()));
  insert.Bind(11, d.relative_heading.value_or(0.0)).Bind(12, d.relative_heading_variance);
  insert.Bind(13, d.confidence).Bind(14, record.received_unix_time);
  if (!RunOrFail(&insert, error)) return PutOutcome::kError;
  *seq = sqlite3_last_insert_rowid(db_);
  if (!transaction.Commit(error)) return PutOutcome::kError;
  return PutOutcome::kInserted;
}

std::vector<DetectionRecord> SqliteMapStore::DetectionsAfter(int64_t seq) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(
      db_,
      "SELECT seq, observer_id, detection_id, observed_id, timestamp, x, y, cov_xx, cov_xy, "
      "cov_yy, has_heading, heading, heading_variance, confidence, received_time FROM detections "
      "WHERE seq > ? ORDER BY seq");
  query.Bind(1, seq);
  std::vector<DetectionRecord> out;
  while (query.Step()) {
    DetectionRecord r;
    r.seq = query.Int(0);
    r.detection.observer_id = query.Text(1);
    r.detection_id = query.Int(2);
    r.detection.observed_id = query.Text(3);
    r.detection.timestamp = query.Double(4);
    r.detection.position_in_observer = Eigen::Vector2d(query.Double(5), query.Double(6));
    r.detection.covariance << query.Double(7), query.Double(8), query.Double(8), query.Double(9);
    if (query.Int(10) != 0) r.detection.relative_heading = query.Double(11);
    r.detection.relative_heading_variance = query.Double(12);
    r.detection.confidence = query.Double(13);
    r.received_unix_time = query.Double(14);
    out.push_back(std::move(r));
  }
  return out;
}

int64_t SqliteMapStore::PutVersion(const VersionRecord& v, const EncodedGrid& grid,
                                   std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteTransaction transaction(db_);
  SqliteStatement insert(
      db_, "INSERT INTO versions (version, created_time, covered_submap_seq, trigger, "
           "merge_engine, grid_width, grid_height, grid_resolution, grid_origin_x, grid_origin_y, "
           "grid_scale, grid_cells) VALUES ((SELECT COALESCE(MAX(version), 0) + 1 FROM versions), "
           "?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  insert.Bind(1, v.created_unix_time).Bind(2, v.covered_submap_seq).Bind(3, v.trigger);
  insert.Bind(4, v.merge_engine).Bind(5, static_cast<int64_t>(grid.geometry.width));
  insert.Bind(6, static_cast<int64_t>(grid.geometry.height)).Bind(7, grid.geometry.resolution);
  insert.Bind(8, grid.geometry.origin.x()).Bind(9, grid.geometry.origin.y());
  insert.Bind(10, static_cast<double>(grid.log_odds_scale)).BindBlob(11, grid.compressed);
  if (!RunOrFail(&insert, error)) return 0;
  const int64_t version = sqlite3_last_insert_rowid(db_);
  for (const std::string& robot_id : v.trigger_robot_ids) {
    SqliteStatement s(db_, "INSERT INTO version_trigger_robots VALUES (?, ?)");
    s.Bind(1, version).Bind(2, robot_id);
    if (!RunOrFail(&s, error)) return 0;
  }
  for (const SubmapKey& key : v.new_submaps) {
    SqliteStatement s(db_, "INSERT INTO version_submaps VALUES (?, ?, ?, ?)");
    s.Bind(1, version).Bind(2, key.robot_id).Bind(3, key.submap_id).Bind(4, key.revision);
    if (!RunOrFail(&s, error)) return 0;
  }
  for (const DetectionRef& ref : v.new_detections) {
    SqliteStatement s(db_, "INSERT INTO version_detections VALUES (?, ?, ?)");
    s.Bind(1, version).Bind(2, ref.observer_id).Bind(3, ref.detection_id);
    if (!RunOrFail(&s, error)) return 0;
  }
  for (const auto& [name, value] : v.quality) {
    SqliteStatement s(db_, "INSERT INTO version_quality VALUES (?, ?, ?)");
    s.Bind(1, version).Bind(2, name).Bind(3, value);
    if (!RunOrFail(&s, error)) return 0;
  }
  for (const RobotPlacementRecord& p : v.placements) {
    SqliteStatement s(db_, "INSERT INTO alignments VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    s.Bind(1, version).Bind(2, p.robot_id).Bind(3, static_cast<int64_t>(p.placed));
    s.Bind(4, p.local_in_global.x()).Bind(5, p.local_in_global.y());
    s.Bind(6, p.local_in_global.rotation()).Bind(7, p.source).Bind(8, p.note);
    if (p.start_in_global) {
      s.Bind(9, p.start_in_global->x()).Bind(10, p.start_in_global->y());
      s.Bind(11, p.start_in_global->rotation());
    }
    if (!RunOrFail(&s, error)) return 0;
  }
  if (options_.retention.keep_version_grids > 0) {
    SqliteStatement prune(db_,
                          "UPDATE versions SET grid_cells = NULL WHERE version <= ? AND "
                          "grid_cells IS NOT NULL");
    prune.Bind(1, version - options_.retention.keep_version_grids);
    if (!RunOrFail(&prune, error)) return 0;
  }
  if (!transaction.Commit(error)) return 0;
  return version;
}

void SqliteMapStore::LoadProvenance(VersionRecord* v) {
  SqliteStatement robots(db_, "SELECT robot_id FROM version_trigger_robots WHERE version = ?");
  robots.Bind(1, v->version);
  while (robots.Step()) v->trigger_robot_ids.push_back(robots.Text(0));
  SqliteStatement submaps(db_,
                          "SELECT robot_id, submap_id, revision FROM version_submaps WHERE "
                          "version = ?");
  submaps.Bind(1, v->version);
  while (submaps.Step()) {
    v->new_submaps.push_back(SubmapKey{submaps.Text(0), submaps.Int(1), submaps.Int(2)});
  }
  SqliteStatement detections(db_,
                             "SELECT observer_id, detection_id FROM version_detections WHERE "
                             "version = ?");
  detections.Bind(1, v->version);
  while (detections.Step()) {
    v->new_detections.push_back(DetectionRef{detections.Text(0), detections.Int(1)});
  }
  SqliteStatement quality(db_, "SELECT name, value FROM version_quality WHERE version = ?");
  quality.Bind(1, v->version);
  while (quality.Step()) v->quality[quality.Text(0)] = quality.Double(1);
  SqliteStatement placements(
      db_,
      "SELECT robot_id, placed, x, y, theta, source, note, start_x, start_y, "
      "start_theta FROM alignments "
      "WHERE version = ? ORDER BY robot_id");
  placements.Bind(1, v->version);
  while (placements.Step()) {
    RobotPlacementRecord p;
    p.robot_id = placements.Text(0);
    p.placed = placements.Int(1) != 0;
    p.local_in_global = Rigid2d(placements.Double(2), placements.Double(3), placements.Double(4));
    p.source = placements.Text(5);
    p.note = placements.Text(6);
    if (!placements.IsNull(7) && !placements.IsNull(8) && !placements.IsNull(9)) {
      p.start_in_global = Rigid2d(placements.Double(7), placements.Double(8), placements.Double(9));
    }
    v->placements.push_back(std::move(p));
  }
}

std::vector<VersionRecord> SqliteMapStore::QueryVersions(const std::string& where_and_order,
                                                         double arg) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_, std::string("SELECT ") + kVersionColumns + " FROM versions " +
                                 where_and_order);
  query.Bind(1, arg);
  std::vector<VersionRecord> out;
  while (query.Step()) out.push_back(VersionFromRow(query));
  for (VersionRecord& v : out) LoadProvenance(&v);
  return out;
}

std::optional<VersionRecord> SqliteMapStore::GetVersion(int64_t version) {
  auto found = QueryVersions("WHERE version = ?", static_cast<double>(version));
  if (found.empty()) return std::nullopt;
  return found.front();
}

std::optional<VersionRecord> SqliteMapStore::LatestVersion() {
  auto found = QueryVersions("WHERE ?1 = ?1 ORDER BY version DESC LIMIT 1", 0.0);
  if (found.empty()) return std::nullopt;
  return found.front();
}

std::optional<VersionRecord> SqliteMapStore::VersionAtTime(double unix_time) {
  auto found = QueryVersions("WHERE created_time <= ? ORDER BY version DESC LIMIT 1", unix_time);
  if (found.empty()) return std::nullopt;
  return found.front();
}

std::vector<VersionRecord> SqliteMapStore::ListVersions(int limit, int64_t before_version) {
  const std::string where = before_version > 0 ? "WHERE version < ?1" : "WHERE ?1 = ?1";
  return QueryVersions(where + " ORDER BY version DESC LIMIT " + std::to_string(limit),
                       before_version > 0 ? static_cast<double>(before_version) : 0.0);
}

std::optional<EncodedGrid> SqliteMapStore::GetVersionGrid(int64_t version) {
  std::lock_guard<std::mutex> lock(mutex_);
  SqliteStatement query(db_,
                        "SELECT grid_width, grid_height, grid_resolution, grid_origin_x, "
                        "grid_origin_y, grid_scale, grid_cells FROM versions WHERE version = ? "
                        "AND grid_cells IS NOT NULL");
  query.Bind(1, version);
  if (!query.Step()) return std::nullopt;
  EncodedGrid grid;
  grid.geometry.width = static_cast<int>(query.Int(0));
  grid.geometry.height = static_cast<int>(query.Int(1));
  grid.geometry.resolution = query.Double(2);
  grid.geometry.origin = Eigen::Vector2d(query.Double(3), query.Double(4));
  grid.log_odds_scale = static_cast<float>(query.Double(5));
  grid.compressed = query.Blob(6);
  return grid;
}

}  // namespace fleetmap
