#ifndef FLEETMAP_ROBOT_AGENT_AGENT_OUTBOX_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_OUTBOX_H_

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

struct sqlite3;

namespace fleetmap {

enum class OutboxKind : int { kSubmap = 1, kTrajectory = 2, kDetection = 3 };
const char* OutboxKindName(OutboxKind kind);

// The natural key of an upload, the same the server deduplicates on: (robot, kind, id,
// revision). Submaps: (submap_id, revision); trajectories: (0, revision); detections:
// (detection_id, 0).
struct OutboxKey {
  std::string robot_id;
  OutboxKind kind = OutboxKind::kSubmap;
  int64_t id = 0;
  int64_t revision = 0;
};

struct OutboxItem {
  int64_t seq = 0;  // insertion order, assigned by the outbox
  OutboxKey key;
  std::string payload;             // the serialized fleetmap.v1 request item
  int attempts = 0;                // failed sends so far
  double next_attempt_time = 0.0;  // Unix seconds
  std::string last_error;
};

struct OutboxCounts {
  int64_t pending = 0;
  int64_t pending_submaps = 0;
  int64_t pending_trajectories = 0;
  int64_t pending_detections = 0;
  int64_t rejected = 0;
};

// The robot's durable queue of uploads (SQLite, WAL, synchronous=FULL): every item is written
// here before anything is sent, and deleted only when the server acknowledged it, so neither a
// crash of the agent nor a lost connection loses data. Items whose natural key is already queued
// are ignored (enqueueing is idempotent). Items the server refused for good move to a
// `rejected` table, kept for inspection.
//
// Thread-safe: the pipeline enqueues while the uploader reads and acknowledges; one mutex guards
// the connection.
class Outbox {
 public:
  // Opens or creates the database. nullptr + `error` when the file is not a usable outbox
  // (corrupt, not SQLite, from a newer version, unwritable).
  static std::unique_ptr<Outbox> Open(const std::string& path, std::string* error);
  ~Outbox();
  Outbox(const Outbox&) = delete;
  Outbox& operator=(const Outbox&) = delete;

  // Queues an item, due at `now`. `*inserted` is false when the key was already queued. With
  // `supersede`, queued items of the same robot, kind and id with an older revision are dropped,
  // and the item itself is dropped when a newer revision is queued (each revision of a submap or
  // trajectory is a full snapshot, so the newest carries everything).
  bool Enqueue(const OutboxKey& key, const std::string& payload, double now, bool supersede,
               bool* inserted, std::string* error);

  // Up to `limit` items of `kind` due at `now` (next_attempt_time <= now), oldest first, with at
  // most `max_bytes` of payload in total (always at least one item when any is due).
  bool Due(OutboxKind kind, double now, int limit, int64_t max_bytes,
           std::vector<OutboxItem>* items, std::string* error);
  // The earliest next_attempt_time of any queued item; false when the outbox is empty.
  bool NextDueTime(double* time, std::string* error);

  // The server stored the item: forget it. Unknown seqs are ignored (e.g. superseded meanwhile).
  bool Acknowledge(const std::vector<int64_t>& seqs, std::string* error);
  // A failed attempt: attempts + 1, retry at `next_attempt_time`.
  bool RecordFailure(int64_t seq, double next_attempt_time, const std::string& message,
                     std::string* error);
  // The server refused the item for good (status `code`): move it to the rejected table.
  bool Reject(int64_t seq, int code, const std::string& message, std::string* error);
  // Makes every queued item due at `now` (after a restart, or when the server came back).
  bool MakeAllDue(double now, std::string* error);

  bool Counts(OutboxCounts* counts, std::string* error);
  // Every rejected item (for tools and tests).
  bool Rejected(std::vector<OutboxItem>* items, std::string* error);

  const std::string& path() const { return path_; }

 private:
  Outbox(std::string path, sqlite3* db) : path_(std::move(path)), db_(db) {}
  bool Exec(const char* sql, std::string* error);
  bool ReadItems(const char* sql, OutboxKind kind, double now, int limit, int64_t max_bytes,
                 std::vector<OutboxItem>* items, std::string* error);

  const std::string path_;
  std::mutex mutex_;
  sqlite3* const db_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_OUTBOX_H_
