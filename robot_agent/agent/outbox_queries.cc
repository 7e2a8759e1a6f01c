// The outbox's reads and state changes after enqueueing: due items, acknowledgements,
// failures, rejections and counts.
#include <sqlite3.h>

#include <utility>

#include "robot_agent/agent/internal/sqlite_statement.h"
#include "robot_agent/agent/outbox.h"

namespace fleetmap {

using internal::Fail;
using internal::Statement;

namespace {

// The columns both the pending and the rejected items' queries start with: seq, robot_id, kind,
// item_id, revision, payload, attempts.
OutboxItem ItemColumns(Statement& select) {
  OutboxItem item;
  item.seq = sqlite3_column_int64(select.get(), 0);
  item.key.robot_id = select.Text(1);
  item.key.kind = static_cast<OutboxKind>(sqlite3_column_int(select.get(), 2));
  item.key.id = sqlite3_column_int64(select.get(), 3);
  item.key.revision = sqlite3_column_int64(select.get(), 4);
  item.payload = select.Text(5);
  item.attempts = sqlite3_column_int(select.get(), 6);
  return item;
}

}  // namespace

bool Outbox::ReadItems(const char* sql, OutboxKind kind, double now, int limit, int64_t max_bytes,
                       std::vector<OutboxItem>* items, std::string* error) {
  items->clear();
  Statement select(db_, sql);
  if (!select.ok()) return Fail(db_, "preparing select", error);
  select.Bind(1, static_cast<int64_t>(kind));
  select.Bind(2, now);
  select.Bind(3, static_cast<int64_t>(limit));
  int64_t bytes = 0;
  int rc;
  while ((rc = select.Step()) == SQLITE_ROW) {
    OutboxItem item = ItemColumns(select);
    item.next_attempt_time = sqlite3_column_double(select.get(), 7);
    item.last_error = select.Text(8);
    bytes += static_cast<int64_t>(item.payload.size());
    if (!items->empty() && bytes > max_bytes) break;
    items->push_back(std::move(item));
  }
  if (rc != SQLITE_ROW && rc != SQLITE_DONE) return Fail(db_, "reading items", error);
  return true;
}

bool Outbox::Due(OutboxKind kind, double now, int limit, int64_t max_bytes,
                 std::vector<OutboxItem>* items, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  return ReadItems(
      "SELECT seq, robot_id, kind, item_id, revision, payload, attempts, next_attempt_time, "
      "last_error FROM pending WHERE kind = ? AND next_attempt_time <= ? ORDER BY seq LIMIT ?",
      kind, now, limit, max_bytes, items, error);
}

bool Outbox::NextDueTime(double* time, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement select(db_, "SELECT MIN(next_attempt_time) FROM pending");
  if (!select.ok() || select.Step() != SQLITE_ROW) return Fail(db_, "next due time", error);
  if (sqlite3_column_type(select.get(), 0) == SQLITE_NULL) return false;
  *time = sqlite3_column_double(select.get(), 0);
  return true;
}

bool Outbox::Acknowledge(const std::vector<int64_t>& seqs, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!Exec("BEGIN IMMEDIATE", error)) return false;
  Statement drop(db_, "DELETE FROM pending WHERE seq = ?");
  if (!drop.ok()) {
    Exec("ROLLBACK", nullptr);
    return Fail(db_, "preparing delete", error);
  }
  for (int64_t seq : seqs) {
    sqlite3_reset(drop.get());
    drop.Bind(1, seq);
    if (drop.Step() != SQLITE_DONE) {
      Fail(db_, "deleting", error);
      Exec("ROLLBACK", nullptr);
      return false;
    }
  }
  return Exec("COMMIT", error);
}

bool Outbox::RecordFailure(int64_t seq, double next_attempt_time, const std::string& message,
                           std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement update(db_,
                   "UPDATE pending SET attempts = attempts + 1, next_attempt_time = ?, "
                   "last_error = ? WHERE seq = ?");
  if (!update.ok()) return Fail(db_, "preparing update", error);
  update.Bind(1, next_attempt_time);
  update.Bind(2, message);
  update.Bind(3, seq);
  if (update.Step() != SQLITE_DONE) return Fail(db_, "recording a failure", error);
  return true;
}

bool Outbox::Reject(int64_t seq, int code, const std::string& message, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!Exec("BEGIN IMMEDIATE", error)) return false;
  Statement move(db_,
                 "INSERT OR REPLACE INTO rejected (seq, robot_id, kind, item_id, revision, "
                 "payload, attempts, code, message, rejected_time) SELECT seq, robot_id, kind, "
                 "item_id, revision, payload, attempts + 1, ?, ?, (julianday('now') - 2440587.5) * "
                 "86400.0 FROM pending "
                 "WHERE seq = ?");
  Statement drop(db_, "DELETE FROM pending WHERE seq = ?");
  if (!move.ok() || !drop.ok()) {
    Exec("ROLLBACK", nullptr);
    return Fail(db_, "preparing reject", error);
  }
  move.Bind(1, static_cast<int64_t>(code));
  move.Bind(2, message);
  move.Bind(3, seq);
  drop.Bind(1, seq);
  if (move.Step() != SQLITE_DONE || drop.Step() != SQLITE_DONE) {
    Fail(db_, "rejecting", error);
    Exec("ROLLBACK", nullptr);
    return false;
  }
  return Exec("COMMIT", error);
}

bool Outbox::MakeAllDue(double now, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  Statement update(db_, "UPDATE pending SET next_attempt_time = ? WHERE next_attempt_time > ?");
  if (!update.ok()) return Fail(db_, "preparing update", error);
  update.Bind(1, now);
  update.Bind(2, now);
  if (update.Step() != SQLITE_DONE) return Fail(db_, "rescheduling", error);
  return true;
}

bool Outbox::Counts(OutboxCounts* counts, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  *counts = OutboxCounts();
  Statement select(db_, "SELECT kind, COUNT(*) FROM pending GROUP BY kind");
  if (!select.ok()) return Fail(db_, "preparing count", error);
  int rc;
  while ((rc = select.Step()) == SQLITE_ROW) {
    const int64_t n = sqlite3_column_int64(select.get(), 1);
    counts->pending += n;
    switch (static_cast<OutboxKind>(sqlite3_column_int(select.get(), 0))) {
      case OutboxKind::kSubmap:
        counts->pending_submaps += n;
        break;
      case OutboxKind::kTrajectory:
        counts->pending_trajectories += n;
        break;
      case OutboxKind::kDetection:
        counts->pending_detections += n;
        break;
    }
  }
  if (rc != SQLITE_DONE) return Fail(db_, "counting", error);
  Statement rejected(db_, "SELECT COUNT(*) FROM rejected");
  if (!rejected.ok() || rejected.Step() != SQLITE_ROW) return Fail(db_, "counting", error);
  counts->rejected = sqlite3_column_int64(rejected.get(), 0);
  return true;
}

bool Outbox::Rejected(std::vector<OutboxItem>* items, std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  items->clear();
  Statement select(db_,
                   "SELECT seq, robot_id, kind, item_id, revision, payload, attempts, message "
                   "FROM rejected ORDER BY seq");
  if (!select.ok()) return Fail(db_, "preparing select", error);
  int rc;
  while ((rc = select.Step()) == SQLITE_ROW) {
    OutboxItem item = ItemColumns(select);
    item.last_error = select.Text(7);
    items->push_back(std::move(item));
  }
  if (rc != SQLITE_DONE) return Fail(db_, "reading rejected items", error);
  return true;
}

}  // namespace fleetmap
