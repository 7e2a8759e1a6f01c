// The server's merge worker once uploads settle, with a join held on probation (issue 8): a real
// server (SQLite store, loopback port), robots uploading through gRPC as agents do.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "map_server/server/map_server.h"
#include "robot_agent/agent/proto_conversions.h"
#include "tests/merge/merge_engine_fixtures.h"
#include "tests/server/server_test_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using merge_fixtures::SimRobot;

class SettleProbationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    MapServerOptions options = testing::LoopbackServerOptions(dir_.path());
    options.settle_seconds = 1.0;
    options.merge_engine.match_join_probation_growth = 1.25;  // the default, which this is about
    std::string error;
    server_ = MapServer::Start(options, &error);
    ASSERT_TRUE(server_) << error;
    stub_ = v1::MapService::NewStub(MakeClientChannel(server_->address()));
  }

  // Registers the robot without a start pose and uploads its submaps and trajectory.
  void Upload(const SimRobot& robot) {
    {
      grpc::ClientContext context;
      v1::RegisterRobotResponse response;
      ASSERT_TRUE(
          stub_->RegisterRobot(&context, testing::MakeRegistration(robot.id, false), &response)
              .ok());
    }
    v1::UploadSubmapsRequest upload;
    upload.set_robot_id(robot.id);
    for (const Submap& s : testing::MakeSubmaps(robot.id, testing::OfficeWorld(), robot.path,
                                                robot.local_in_world, 10, merge_fixtures::kDt)) {
      *upload.add_submaps() = agent::ToProto(s);
    }
    {
      grpc::ClientContext context;
      v1::UploadSubmapsResponse acks;
      ASSERT_TRUE(stub_->UploadSubmaps(&context, upload, &acks).ok());
      for (const v1::ItemAck& ack : acks.acks()) ASSERT_EQ(ack.code(), 0) << ack.message();
    }
    grpc::ClientContext context;
    v1::UploadTrajectoryResponse response;
    ASSERT_TRUE(stub_
                    ->UploadTrajectory(&context,
                                       agent::ToTrajectoryRequest(
                                           robot.id, 1,
                                           testing::MakeTrajectory(robot.path, robot.local_in_world,
                                                                   merge_fixtures::kDt)),
                                       &response)
                    .ok());
  }

  // Every version so far, oldest first.
  std::vector<v1::VersionInfo> Versions() {
    grpc::ClientContext context;
    v1::ListVersionsRequest request;
    request.set_limit(1000);
    v1::ListVersionsResponse response;
    EXPECT_TRUE(stub_->ListVersions(&context, request, &response).ok());
    std::vector<v1::VersionInfo> versions(response.versions().begin(), response.versions().end());
    std::sort(versions.begin(), versions.end(),
              [](const auto& x, const auto& y) { return x.version() < y.version(); });
    return versions;
  }

  const testing::ScopedTempDir dir_{"settle_probation"};  // outlives the server below
  std::unique_ptr<MapServer> server_;
  std::unique_ptr<v1::MapService::Stub> stub_;
};

const v1::RobotPlacement* Find(const v1::VersionInfo& version, const std::string& robot) {
  for (const v1::RobotPlacement& p : version.placements()) {
    if (p.robot_id() == robot) return &p;
  }
  return nullptr;
}

// Robot b's join on robot a passes on matches alone, so it is held on probation until the maps
// grow by 1.25. a's 4 submaps come first, then b's 3 (b's first two alone do not place it):
// however the worker batches them, the join first passes with 6 or 7 submaps, and 7 never ends
// the probation. No growth comes: once the uploads settle, the merge as fed judges the held join
// on the maps as they are, and places b, as the settled rebuild does. The settled version says
// so: 2 robots placed as fed (1 without the judgement).
TEST_F(SettleProbationTest, AJoinHeldOnProbationIsMadeOnceUploadsSettle) {
  SimRobot a = merge_fixtures::RobotA(), b = merge_fixtures::RobotB(-2.4);
  a.path.resize(40);
  b.path.resize(30);
  Upload(a);
  Upload(b);
  const std::vector<v1::VersionInfo> before = Versions();
  const int64_t uploaded = before.empty() ? 0 : before.back().version();

  // The settled version that saw b's uploads (a loaded machine may settle on a's alone first).
  std::optional<v1::VersionInfo> settled;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!settled && std::chrono::steady_clock::now() < deadline) {
    for (const v1::VersionInfo& v : Versions()) {
      if (v.version() > uploaded && Find(v, "b") &&
          v.provenance().trigger().rfind("uploads settled", 0) == 0) {
        settled = v;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(settled) << "no version came once the uploads settled";

  // Held as fed: no version before the settled one placed b.
  for (const v1::VersionInfo& v : Versions()) {
    if (v.version() >= settled->version()) break;
    const v1::RobotPlacement* placement = Find(v, "b");
    EXPECT_FALSE(placement && placement->placed())
        << "version " << v.version() << " placed b before the uploads settled: " << placement->note();
  }
  const std::string& trigger = settled->provenance().trigger();
  EXPECT_NE(trigger.find("placing 2 robot(s) against 2 as fed"), std::string::npos) << trigger;
  const v1::RobotPlacement* pa = Find(*settled, "a");
  const v1::RobotPlacement* pb = Find(*settled, "b");
  ASSERT_TRUE(pa && pa->placed() && pb && pb->placed());
  const Rigid2d estimated = FromProto(pa->start_in_global()).inverse() * FromProto(pb->start_in_global());
  EXPECT_THAT(estimated, testing::IsNearPose(merge_fixtures::TrueRelative(a, b), 0.03, 0.3 * M_PI / 180));
}

}  // namespace
}  // namespace fleetmap
