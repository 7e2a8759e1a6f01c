#include "robot_agent/agent/outbox.h"

#include <sqlite3.h>

#include <utility>

#include "robot_agent/agent/internal/sqlite_statement.h"

namespace fleetmap {

using internal::Fail;
using internal::Statement;

namespace {

constexpr int kSchemaVersion = 1;

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS pending (
  seq INTEGER PRIMARY KEY AUTOINCREMENT,
  robot_id TEXT NOT NULL,
  kind INTEGER NOT NULL,
  item_id INTEGER NOT NULL,
  revision INTEGER NOT NULL,
  payload BLOB NOT NULL,
  attempts INTEGER NOT NULL DEFAULT 0,
  next_attempt_time REAL NOT NULL,
  created_time REAL NOT NULL,
  last_error TEXT NOT NULL DEFAULT '',
  UNIQUE (robot_id, kind, item_id, revision));
CREATE INDEX IF NOT EXISTS pending_due ON pending (kind, next_attempt_time);
CREATE TABLE IF NOT EXISTS rejected (
  seq INTEGER PRIMARY KEY,
  robot_id TEXT NOT NULL,
  kind INTEGER NOT NULL,
  item_id INTEGER NOT NULL,
  revision INTEGER NOT NULL,
  payload BLOB NOT NULL,
  attempts INTEGER NOT NULL,
  code INTEGER NOT NULL,
  message TEXT NOT NULL,
  rejected_time REAL NOT NULL);
)sql";

}  // namespace

const char* OutboxKindName(OutboxKind kind) {
  switch (kind) {
    case OutboxKind::kSubmap:
      return "submap";
    case OutboxKind::kTrajectory:
      return "trajectory";
    case OutboxKind::kDetection:
      return "detection";
  }
  return "unknown";
}

std::unique_ptr<Outbox> Outbox::Open(const std::string& path, std::string* error) {
  sqlite3* db = nullptr;
  const int rc =
      sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr);
  if (rc != SQLITE_OK) {
    if (error) {
      *error =
          "outbox " + path + ": cannot open: " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
    }
    sqlite3_close(db);
    return nullptr;
  }
  std::unique_ptr<Outbox> outbox(new Outbox(path, db));
  sqlite3_busy_timeout(db, 5000);
  std::string why;
  // The first statements read the header: a file that is not SQLite fails here.
  if (!outbox->Exec("PRAGMA journal_mode=WAL", &why) ||
      !outbox->Exec("PRAGMA synchronous=FULL", &why)) {
    if (error) {
      *error = "outbox " + path + " is not a usable SQLite database (" + why +
               "); move it away to start with an empty outbox";
    }
    return nullptr;
  }
  {
    Statement check(db, "PRAGMA quick_check");
    const int step = check.ok() ? check.Step() : SQLITE_ERROR;
    if (step != SQLITE_ROW || check.Text(0) != "ok") {
      if (error) {
        *error = "outbox " + path + " is corrupt (" +
                 (step == SQLITE_ROW ? check.Text(0) : std::string(sqlite3_errmsg(db))) +
                 "); move it away to start with an empty outbox";
      }
      return nullptr;
    }
  }
  int64_t version = 0;
  {
    Statement get(db, "PRAGMA user_version");
    if (!get.ok() || get.Step() != SQLITE_ROW) {
      Fail(db, "reading the schema version of " + path, error);
      return nullptr;
    }
    version = sqlite3_column_int64(get.get(), 0);
  }
  if (version > kSchemaVersion) {
    if (error) {
      *error = "outbox " + path + " has schema version " + std::to_string(version) +
               ", newer than this agent's " + std::to_string(kSchemaVersion) +
               "; use a newer fleetmap-agent or another outbox path";
    }
    return nullptr;
  }
  if (!outbox->Exec(kSchema, &why) ||
      !outbox->Exec(("PRAGMA user_version=" + std::to_string(kSchemaVersion)).c_str(), &why)) {
    if (error) *error = "outbox " + path + ": cannot create the schema: " + why;
    return nullptr;
  }
  return outbox;
}

Outbox::~Outbox() { sqlite3_close(db_); }

bool Outbox::Exec(const char* sql, std::string* error) {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &message) != SQLITE_OK) {
    if (error) *error = message ? message : sqlite3_errmsg(db_);
    sqlite3_free(message);
    return false;
  }
  return true;
}

bool Outbox::Enqueue(const OutboxKey& key, const std::string& payload, double now, bool supersede,
                     bool* inserted, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!Exec("BEGIN IMMEDIATE", error)) return false;
  auto rollback = [&](const std::string& what) {
    Fail(db_, what, error);
    Exec("ROLLBACK", nullptr);
    return false;
  };
  if (supersede) {
    // A newer revision already waits: this one is superseded on arrival.
    Statement newer(db_,
                    "SELECT 1 FROM pending WHERE robot_id = ? AND kind = ? AND item_id = ? AND "
                    "revision > ? LIMIT 1");
    if (!newer.ok()) return rollback("preparing supersede check");
    newer.Bind(1, key.robot_id);
    newer.Bind(2, static_cast<int64_t>(key.kind));
    newer.Bind(3, key.id);
    newer.Bind(4, key.revision);
    const int rc = newer.Step();
    if (rc == SQLITE_ROW) {
      if (inserted) *inserted = false;
      return Exec("COMMIT", error);
    }
    if (rc != SQLITE_DONE) return rollback("checking for newer revisions");
  }
  Statement insert(db_,
                   "INSERT OR IGNORE INTO pending (robot_id, kind, item_id, revision, payload, "
                   "next_attempt_time, created_time) VALUES (?, ?, ?, ?, ?, ?, ?)");
  if (!insert.ok()) return rollback("preparing insert");
  insert.Bind(1, key.robot_id);
  insert.Bind(2, static_cast<int64_t>(key.kind));
  insert.Bind(3, key.id);
  insert.Bind(4, key.revision);
  insert.BindBlob(5, payload);
  insert.Bind(6, now);
  insert.Bind(7, now);
  if (insert.Step() != SQLITE_DONE) return rollback("inserting");
  const bool added = sqlite3_changes(db_) > 0;
  if (added && supersede) {
    Statement drop(db_,
                   "DELETE FROM pending WHERE robot_id = ? AND kind = ? AND item_id = ? AND "
                   "revision < ?");
    if (!drop.ok()) return rollback("preparing supersede");
    drop.Bind(1, key.robot_id);
    drop.Bind(2, static_cast<int64_t>(key.kind));
    drop.Bind(3, key.id);
    drop.Bind(4, key.revision);
    if (drop.Step() != SQLITE_DONE) return rollback("superseding");
  }
  if (!Exec("COMMIT", error)) {
    Exec("ROLLBACK", nullptr);
    return false;
  }
  if (inserted) *inserted = added;
  return true;
}

}  // namespace fleetmap
