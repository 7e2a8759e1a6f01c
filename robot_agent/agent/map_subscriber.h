#ifndef FLEETMAP_ROBOT_AGENT_AGENT_MAP_SUBSCRIBER_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_MAP_SUBSCRIBER_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/agent/backoff.h"
#include "shared/codec/grid_codec.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

// Where the server places one robot in the global frame.
struct RobotInGlobal {
  std::string robot_id;
  bool placed = false;
  Rigid2d local_in_global;                 // when placed
  std::optional<StampedPose> latest_pose;  // robot in the global frame, when known
};

// The newest global map version the robot knows of.
struct GlobalMapView {
  int64_t version = 0;
  double created_unix_time = 0.0;
  bool has_grid = false;
  QuantizedGrid grid;  // global frame
  std::vector<RobotInGlobal> robots;
};

struct MapSubscriberOptions {
  BackoffOptions reconnect;
  double rpc_timeout = 10.0;  // for the robot-pose query after each version
  // Optional: keep the latest map as `<file>.pgm` + `<file>.yaml`.
  std::string file;
};

// Follows the server's global map: a SubscribeMapUpdates stream (with grids), the robots' poses
// after each version, reconnecting with backoff whenever the stream breaks. The robot can read
// the newest version at any time.
//
// One thread of its own; latest() and the counters are safe from any thread.
class MapSubscriber {
 public:
  MapSubscriber(const MapSubscriberOptions& options,
                std::shared_ptr<grpc::ChannelInterface> channel);
  ~MapSubscriber();
  MapSubscriber(const MapSubscriber&) = delete;
  MapSubscriber& operator=(const MapSubscriber&) = delete;

  void Start();
  void Stop();  // cancels the stream and joins

  // nullptr before the first version arrives.
  std::shared_ptr<const GlobalMapView> latest() const;
  bool streaming() const { return streaming_; }
  int64_t versions_received() const { return versions_received_; }
  int64_t reconnects() const { return reconnects_; }
  const std::string last_error() const;

 private:
  void Loop();
  // Decodes one update and replaces the latest view.
  void Apply(const v1::MapUpdate& update);
  void QueryRobots(GlobalMapView* view);
  void SaveFile(const GlobalMapView& view);

  const MapSubscriberOptions options_;
  const std::unique_ptr<v1::MapService::Stub> stub_;
  std::mt19937 random_;

  mutable std::mutex mutex_;  // guards the fields below
  std::condition_variable wake_;
  bool stop_ = false;
  grpc::ClientContext* active_call_ = nullptr;
  std::shared_ptr<const GlobalMapView> latest_;
  std::string last_error_;
  std::atomic<bool> streaming_{false};
  std::atomic<int64_t> versions_received_{0};
  std::atomic<int64_t> reconnects_{0};
  std::thread thread_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_MAP_SUBSCRIBER_H_
