// A real server (SQLite store, loopback port) and a real client in one process.
#include <gtest/gtest.h>

#include <optional>
#include <thread>

#include "map_server/server/map_server.h"
#include "tests/server/server_test_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

class InProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    MapServerOptions options = testing::LoopbackServerOptions(dir_.path());
    options.max_request_bytes = 1 << 20;
    std::string error;
    server_ = MapServer::Start(options, &error);
    ASSERT_TRUE(server_) << error;
    stub_ = v1::MapService::NewStub(MakeClientChannel(server_->address()));
  }

  const testing::ScopedTempDir dir_{"inprocess"};  // outlives the server below
  std::unique_ptr<MapServer> server_;
  std::unique_ptr<v1::MapService::Stub> stub_;
};

TEST_F(InProcessTest, UploadQueryAndSubscribe) {
  {
    grpc::ClientContext context;
    v1::RegisterRobotResponse response;
    ASSERT_TRUE(stub_->RegisterRobot(&context, testing::MakeRegistration("r1", true), &response).ok());
  }
  // A subscriber started before the uploads sees versions arrive.
  grpc::ClientContext subscribe_context;
  subscribe_context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
  v1::SubscribeMapUpdatesRequest subscribe_request;
  subscribe_request.set_include_grid(true);
  auto reader = stub_->SubscribeMapUpdates(&subscribe_context, subscribe_request);

  v1::UploadSubmapsRequest upload;
  upload.set_robot_id("r1");
  *upload.add_submaps() = testing::MakeSubmapUpload(0, 0);
  *upload.add_submaps() = testing::MakeSubmapUpload(1, 0, Rigid2d(2.0, 0.0, 0.0));
  v1::UploadSubmapsResponse acks;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(stub_->UploadSubmaps(&context, upload, &acks).ok());
  }
  ASSERT_EQ(acks.acks_size(), 2);
  EXPECT_EQ(acks.acks(1).code(), 0);

  v1::MapUpdate update;
  bool saw_both = false;
  while (!saw_both && reader->Read(&update)) {
    saw_both = update.map().grid().width() == 80;
  }
  EXPECT_TRUE(saw_both);
  subscribe_context.TryCancel();
  reader->Finish();

  // A crop at a coarser resolution.
  v1::GetGlobalMapRequest request;
  request.mutable_bbox()->set_min_x(0.0);
  request.mutable_bbox()->set_min_y(0.0);
  request.mutable_bbox()->set_max_x(1.0);
  request.mutable_bbox()->set_max_y(2.0);
  request.set_resolution(0.1);
  v1::GlobalMap map;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(stub_->GetGlobalMap(&context, request, &map).ok());
  }
  EXPECT_EQ(map.grid().width(), 10);
  EXPECT_EQ(map.grid().height(), 20);

  v1::ListVersionsResponse versions;
  grpc::ClientContext context;
  ASSERT_TRUE(stub_->ListVersions(&context, v1::ListVersionsRequest(), &versions).ok());
  ASSERT_GE(versions.versions_size(), 1);
}

TEST_F(InProcessTest, OversizeRequestIsResourceExhausted) {
  v1::UploadSubmapsRequest upload;
  upload.set_robot_id("r1");
  upload.add_submaps()->mutable_grid()->set_cells_zstd(std::string(2 << 20, 'x'));
  v1::UploadSubmapsResponse acks;
  grpc::ClientContext context;
  EXPECT_EQ(stub_->UploadSubmaps(&context, upload, &acks).error_code(),
            grpc::StatusCode::RESOURCE_EXHAUSTED);
}

TEST_F(InProcessTest, OutOfOrderTrajectoryIsFailedPrecondition) {
  grpc::ClientContext register_context;
  v1::RegisterRobotResponse registered;
  ASSERT_TRUE(stub_->RegisterRobot(&register_context, testing::MakeRegistration("r1", false),
                                   &registered).ok());
  v1::UploadTrajectoryRequest request;
  request.set_robot_id("r1");
  request.set_revision(5);
  ToProto(StampedPose{1.0, Rigid2d(1, 0, 0)}, request.add_poses());
  v1::UploadTrajectoryResponse response;
  {
    grpc::ClientContext context;
    ASSERT_TRUE(stub_->UploadTrajectory(&context, request, &response).ok());
  }
  request.set_revision(4);
  grpc::ClientContext context;
  EXPECT_EQ(stub_->UploadTrajectory(&context, request, &response).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
}

// Once uploads stop for settle_seconds, the engine worker rebuilds the merge from the store
// with everything at once (MergeEngineWorkerOptions::settle_seconds) and publishes it. Returns
// that version, if one came within `wait_seconds`.
std::optional<v1::VersionInfo> SettledVersion(double settle_seconds, double wait_seconds) {
  const testing::ScopedTempDir dir("settle");
  MapServerOptions options = testing::LoopbackServerOptions(dir.path());
  options.settle_seconds = settle_seconds;
  std::string error;
  const auto server = MapServer::Start(options, &error);
  EXPECT_TRUE(server) << error;
  if (!server) return std::nullopt;
  const auto stub = v1::MapService::NewStub(MakeClientChannel(server->address()));
  {
    grpc::ClientContext context;
    v1::RegisterRobotResponse response;
    EXPECT_TRUE(
        stub->RegisterRobot(&context, testing::MakeRegistration("r1", false), &response).ok());
  }
  v1::UploadSubmapsRequest upload;
  upload.set_robot_id("r1");
  *upload.add_submaps() = testing::MakeSubmapUpload(0, 0);
  *upload.add_submaps() = testing::MakeSubmapUpload(1, 0, Rigid2d(2.0, 0.0, 0.0));
  {
    grpc::ClientContext context;
    v1::UploadSubmapsResponse acks;
    EXPECT_TRUE(stub->UploadSubmaps(&context, upload, &acks).ok());
  }
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    grpc::ClientContext context;
    v1::ListVersionsResponse versions;
    EXPECT_TRUE(stub->ListVersions(&context, v1::ListVersionsRequest(), &versions).ok());
    for (const v1::VersionInfo& v : versions.versions()) {
      if (v.provenance().trigger().rfind("uploads settled", 0) == 0) return v;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return std::nullopt;
}

TEST(MergeSettleTest, OnceUploadsStopTheMergeIsRebuiltFromTheStore) {
  const auto version = SettledVersion(0.2, 10.0);
  ASSERT_TRUE(version) << "no version says the merge was rebuilt once uploads settled";
  EXPECT_EQ(version->provenance().trigger().rfind("uploads settled: rebuilt from the store", 0), 0u)
      << version->provenance().trigger();
  ASSERT_EQ(version->placements_size(), 1);
  EXPECT_TRUE(version->placements(0).placed()) << "the rebuild keeps the robot placed";
}

// Without settling no such version comes (so the test above can fail).
TEST(MergeSettleTest, WithSettlingOffNoRebuildFollows) { EXPECT_FALSE(SettledVersion(0.0, 2.0)); }

}  // namespace
}  // namespace fleetmap
