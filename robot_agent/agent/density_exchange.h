#ifndef FLEETMAP_ROBOT_AGENT_AGENT_DENSITY_EXCHANGE_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_DENSITY_EXCHANGE_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/agent/backoff.h"
#include "robot_agent/localization/pose_density.h"

namespace fleetmap {

struct DensityExchangeOptions {
  std::string robot_id;
  BackoffOptions reconnect;
  double rpc_timeout = 2.0;  // seconds, per SendPoseDensity
  // Densities waiting to be sent or applied; beyond this the oldest are dropped (a stale one is
  // worth less than a fresh one, and the filter must not fall behind).
  size_t queue_limit = 16;
};

struct DensityExchangeStats {
  int64_t sent = 0;         // accepted by the server
  int64_t delivered = 0;    // ... and handed to at least one subscription of the seen robot
  int64_t send_failed = 0;  // refused or the server unreachable (then dropped, not retried)
  int64_t received = 0;     // about this robot, from others
  int64_t dropped = 0;      // queue overflow, either way
};

// Collaborative localization over the server (fleetmap.v1 SendPoseDensity /
// SubscribePoseDensities): sends the densities this robot computes for robots it sees, and
// receives the ones others compute for it. Live only: nothing goes through the outbox, because
// a density applied late would move the belief to where the robot was, not where it is.
//
// Two threads of its own (sender, subscription with reconnects); the calls are thread-safe.
class DensityExchange {
 public:
  DensityExchange(const DensityExchangeOptions& options,
                  std::shared_ptr<grpc::ChannelInterface> channel);
  ~DensityExchange();
  DensityExchange(const DensityExchange&) = delete;
  DensityExchange& operator=(const DensityExchange&) = delete;

  void Start();
  void Stop();

  // Queues a density for sending (never blocks).
  void Send(const PoseDensity& density);
  // The densities received since the previous call, oldest first.
  std::vector<PoseDensity> TakeReceived();

  DensityExchangeStats stats() const;
  bool subscribed() const { return subscribed_; }

 private:
  void SendLoop();
  void SubscribeLoop();
  // Waits `seconds` or until Stop(); false when stopped.
  bool Wait(double seconds);

  const DensityExchangeOptions options_;
  const std::unique_ptr<v1::MapService::Stub> stub_;

  mutable std::mutex mutex_;  // guards everything below but the atomics
  std::condition_variable wake_;
  bool stop_ = false;
  grpc::ClientContext* active_call_ = nullptr;
  std::deque<PoseDensity> outgoing_;
  std::vector<PoseDensity> received_;
  DensityExchangeStats stats_;
  std::mt19937 random_;
  std::atomic<bool> subscribed_{false};
  std::thread sender_;
  std::thread subscriber_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_DENSITY_EXCHANGE_H_
