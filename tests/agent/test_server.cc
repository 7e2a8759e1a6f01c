#include "tests/agent/test_server.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "robot_agent/agent/proto_conversions.h"
#include "tests/support/test_support.h"

namespace fleetmap::testing {

std::unique_ptr<MapServer> StartServer(int port, const std::string& db_path) {
  MapServerOptions options;
  options.db_path = db_path;
  options.listen = "127.0.0.1:" + std::to_string(port);
  std::string error;
  std::unique_ptr<MapServer> server = MapServer::Start(options, &error);
  if (!server) ADD_FAILURE() << "server on port " << port << ": " << error;
  return server;
}

std::unique_ptr<MapServer> RestartServer(int port, const std::string& db_path) {
  MapServerOptions options;
  options.db_path = db_path;
  options.listen = "127.0.0.1:" + std::to_string(port);
  std::string error;
  for (int attempt = 0; attempt < 50; ++attempt) {
    std::unique_ptr<MapServer> server = MapServer::Start(options, &error);
    if (server) return server;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ADD_FAILURE() << "cannot restart the server on port " << port << ": " << error;
  return nullptr;
}

LossyProxy::LossyProxy(std::shared_ptr<grpc::Channel> backend, int lose_acks)
    : backend_(v1::MapService::NewStub(backend)), to_lose_(lose_acks) {
  grpc::ServerBuilder builder;
  builder.AddListeningPort("127.0.0.1:0", grpc::InsecureServerCredentials(), &port_);
  builder.RegisterService(this);
  server_ = builder.BuildAndStart();
}

LossyProxy::~LossyProxy() {
  if (server_) server_->Shutdown(std::chrono::system_clock::now());
}

grpc::Status LossyProxy::Lose(const grpc::Status& forwarded) {
  if (forwarded.ok() && to_lose_.fetch_sub(1) > 0) {
    ++lost_;
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, "connection lost (test proxy)");
  }
  return forwarded;
}

grpc::Status LossyProxy::RegisterRobot(grpc::ServerContext*,
                                       const v1::RegisterRobotRequest* request,
                                       v1::RegisterRobotResponse* response) {
  grpc::ClientContext context;
  return backend_->RegisterRobot(&context, *request, response);
}

grpc::Status LossyProxy::UploadSubmaps(grpc::ServerContext*,
                                       const v1::UploadSubmapsRequest* request,
                                       v1::UploadSubmapsResponse* response) {
  grpc::ClientContext context;
  return Lose(backend_->UploadSubmaps(&context, *request, response));
}

grpc::Status LossyProxy::UploadTrajectory(grpc::ServerContext*,
                                          const v1::UploadTrajectoryRequest* request,
                                          v1::UploadTrajectoryResponse* response) {
  grpc::ClientContext context;
  return Lose(backend_->UploadTrajectory(&context, *request, response));
}

grpc::Status LossyProxy::ReportDetections(grpc::ServerContext*,
                                          const v1::ReportDetectionsRequest* request,
                                          v1::ReportDetectionsResponse* response) {
  grpc::ClientContext context;
  return Lose(backend_->ReportDetections(&context, *request, response));
}

Submap MakeSubmap(const std::string& robot_id, int64_t id, int64_t revision) {
  Submap submap;
  submap.robot_id = robot_id;
  submap.submap_id = id;
  submap.revision = revision;
  submap.finished = true;
  submap.submap_in_local = Rigid2d(0.5 * static_cast<double>(id), 0.0, 0.0);
  const Rigid2d robot_in_submap(0.0, 0.0, 0.1 * static_cast<double>(id));
  const SegmentWorld world = BoxWorld({-3.0, -2.0}, {3.0, 2.0});
  submap.grid.InsertScan(SimulateScan(world, robot_in_submap), robot_in_submap);
  submap.scan_poses.push_back(
      {100.0 + static_cast<double>(id), submap.submap_in_local * robot_in_submap});
  return submap;
}

std::string SubmapPayload(const std::string& robot_id, int64_t id, int64_t revision) {
  return agent::ToProto(MakeSubmap(robot_id, id, revision)).SerializeAsString();
}

void QueueSubmaps(Outbox* outbox, const std::string& robot_id, int64_t first_id, int count) {
  for (int64_t id = first_id; id < first_id + count; ++id) {
    bool inserted = false;
    std::string error;
    ASSERT_TRUE(outbox->Enqueue({robot_id, OutboxKind::kSubmap, id, 1},
                                SubmapPayload(robot_id, id, 1), 0.0, true, &inserted, &error))
        << error;
  }
}

}  // namespace fleetmap::testing
