#ifndef FLEETMAP_ROBOT_AGENT_AGENT_UPLOADER_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_UPLOADER_H_

#include <grpcpp/grpcpp.h>

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/agent/backoff.h"
#include "robot_agent/agent/outbox.h"

namespace fleetmap {

struct UploaderOptions {
  int max_batch_items = 32;             // submaps or detections per request
  int64_t max_batch_bytes = 2LL << 20;  // payload per request (the server takes 4 MiB)
  BackoffOptions backoff;
  double rpc_timeout = 10.0;  // seconds per call
  double idle_poll = 1.0;     // seconds between outbox checks when idle
};

enum class ConnectionState { kConnecting, kConnected, kDisconnected };
const char* ConnectionStateName(ConnectionState state);

struct UploaderStats {
  ConnectionState state = ConnectionState::kConnecting;
  bool registered = false;
  int64_t acked_submaps = 0;  // acknowledged by the server, duplicates included
  int64_t acked_trajectories = 0;
  int64_t acked_detections = 0;
  int64_t duplicates = 0;  // acknowledged as already stored
  int64_t superseded = 0;  // the server already held a newer revision: dropped
  int64_t rejected = 0;    // refused for good, moved to the outbox's rejected table
  int64_t failed_calls = 0;
  std::string last_error;  // of the last failed call
};

// Sends what the outbox holds to the server, oldest first, and deletes an item only once the
// server acknowledged it. Failed calls are retried with exponential backoff (per item, and for
// the connection as a whole); items the server refuses for good are moved aside, never retried
// forever. Registers the robot first, and again when the server has forgotten it.
//
// One thread of its own; stats() and the waits are safe from any thread.
class Uploader {
 public:
  Uploader(const UploaderOptions& options, Outbox* outbox,
           std::shared_ptr<grpc::ChannelInterface> channel,
           const v1::RegisterRobotRequest& registration, std::function<double()> clock = nullptr);
  ~Uploader();
  Uploader(const Uploader&) = delete;
  Uploader& operator=(const Uploader&) = delete;

  void Start();
  // Stops the thread (an RPC in flight is cancelled). Queued items stay in the outbox.
  void Stop();
  // Something was enqueued: send without waiting for the next poll.
  void Notify();

  // Waits until the outbox holds nothing pending; false after `timeout` seconds.
  bool WaitUntilEmpty(double timeout);
  UploaderStats stats() const;

  // One pass over the outbox (register if needed, then one batch of each kind that is due);
  // what the thread runs. Public for tests that drive the uploader without its thread.
  enum class Round { kIdle, kProgress, kFailed };
  Round RunRound();

 private:
  enum class Outcome { kOk, kFailed };
  void Loop();
  bool Register();
  Outcome SendSubmaps(const std::vector<OutboxItem>& items);
  Outcome SendTrajectory(const OutboxItem& item);
  Outcome SendDetections(const std::vector<OutboxItem>& items);
  // Applies per-item acknowledgements of a batch.
  void ApplyAcks(const std::vector<OutboxItem>& items,
                 const google::protobuf::RepeatedPtrField<v1::ItemAck>& acks);
  // A call failed as a whole: retry, re-register, or refuse the items.
  Outcome HandleCallFailure(const grpc::Status& status, const std::vector<OutboxItem>& items);
  void RetryLater(const OutboxItem& item, const std::string& message);
  void RejectItem(const OutboxItem& item, int code, const std::string& message);
  void Acknowledge(const std::vector<OutboxItem>& items, int64_t duplicates);
  void DropSuperseded(const std::vector<OutboxItem>& items);
  // Runs `rpc` on `context` with the call deadline, cancellable by Stop().
  grpc::Status Call(grpc::ClientContext* context, const std::function<grpc::Status()>& rpc);
  void NoteError(const std::string& message);
  double Delay(int attempt);

  const UploaderOptions options_;
  Outbox* const outbox_;
  const std::unique_ptr<v1::MapService::Stub> stub_;
  const v1::RegisterRobotRequest registration_;
  const std::function<double()> clock_;
  std::mt19937 random_;  // jitter; only the upload thread draws

  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable wake_;
  std::condition_variable progress_;
  bool stop_ = false;
  bool notified_ = false;
  UploaderStats stats_;
  int consecutive_failures_ = 0;
  int single_item_rounds_ = 0;  // send one item per call while > 0 (after a refused batch)
  grpc::ClientContext* active_call_ = nullptr;
  std::thread thread_;
};

// Unix time in seconds.
double UnixNow();

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_UPLOADER_H_
