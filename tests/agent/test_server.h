#ifndef FLEETMAP_TESTS_AGENT_TEST_SERVER_H_
#define FLEETMAP_TESTS_AGENT_TEST_SERVER_H_

#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server/map_server.h"
#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "robot_agent/agent/outbox.h"
#include "shared/core/submap.h"

namespace fleetmap::testing {

// The real map server on 127.0.0.1 (SQLite when `db_path` is set, else in memory); `port` 0
// lets the OS choose. nullptr when it cannot listen (e.g. the port was taken meanwhile).
std::unique_ptr<MapServer> StartServer(int port, const std::string& db_path = "");
// Starts on `port`, retrying for a while (a port just released can take a moment).
std::unique_ptr<MapServer> RestartServer(int port, const std::string& db_path);

// A proxy in front of a server that forwards uploads but loses the acknowledgement of the
// first `lose_acks` upload calls (the server stored them; the robot hears UNAVAILABLE), the
// way a connection dropping at the wrong moment does.
class LossyProxy final : public v1::MapService::Service {
 public:
  LossyProxy(std::shared_ptr<grpc::Channel> backend, int lose_acks);
  ~LossyProxy() override;
  int port() const { return port_; }
  int lost_acks() const { return lost_; }

  grpc::Status RegisterRobot(grpc::ServerContext*, const v1::RegisterRobotRequest* request,
                             v1::RegisterRobotResponse* response) override;
  grpc::Status UploadSubmaps(grpc::ServerContext*, const v1::UploadSubmapsRequest* request,
                             v1::UploadSubmapsResponse* response) override;
  grpc::Status UploadTrajectory(grpc::ServerContext*, const v1::UploadTrajectoryRequest* request,
                                v1::UploadTrajectoryResponse* response) override;
  grpc::Status ReportDetections(grpc::ServerContext*, const v1::ReportDetectionsRequest* request,
                                v1::ReportDetectionsResponse* response) override;

 private:
  grpc::Status Lose(const grpc::Status& forwarded);
  std::unique_ptr<v1::MapService::Stub> backend_;
  std::atomic<int> to_lose_;
  std::atomic<int> lost_{0};
  std::unique_ptr<grpc::Server> server_;
  int port_ = 0;
};

// A small real submap (one scan in a box room) with the given key, as an outbox payload.
Submap MakeSubmap(const std::string& robot_id, int64_t id, int64_t revision);
std::string SubmapPayload(const std::string& robot_id, int64_t id, int64_t revision);

// Queues `count` finished submaps (ids first_id..) into the outbox.
void QueueSubmaps(Outbox* outbox, const std::string& robot_id, int64_t first_id, int count);

// Polls `done()` every 10 ms until it holds or about `seconds` passed; its last value.
template <typename F>
bool WaitFor(F done, double seconds) {
  for (int i = 0; i < seconds * 100; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return done();
}

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_AGENT_TEST_SERVER_H_
