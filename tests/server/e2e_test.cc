// fleetmap-server as a process on a loopback port, driven by fleetmapctl and a client.
#include <signal.h>
#include <sqlite3.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "map_server/server/map_server.h"
#include "map_server/store/sqlite_map_store.h"
#include "tests/server/process_util.h"
#include "tests/server/server_test_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::RunCtl;

void Register(v1::MapService::Stub* stub, const std::string& id, bool placed) {
  grpc::ClientContext context;
  v1::RegisterRobotResponse response;
  ASSERT_TRUE(stub->RegisterRobot(&context, testing::MakeRegistration(id, placed), &response).ok());
}

v1::ItemAck UploadOne(v1::MapService::Stub* stub, const std::string& robot, int64_t id,
                      grpc::Status* status) {
  v1::UploadSubmapsRequest request;
  request.set_robot_id(robot);
  *request.add_submaps() = testing::MakeSubmapUpload(id, 0, Rigid2d(0.5 * (id % 20), 0.3 * (id / 20), 0));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  v1::UploadSubmapsResponse response;
  *status = stub->UploadSubmaps(&context, request, &response);
  return response.acks_size() > 0 ? response.acks(0) : v1::ItemAck();
}

TEST(ServerProcessTest, CtlCommandsAgainstARunningServer) {
  const testing::ScopedTempDir temp("e2e_ctl");
  const std::string& dir = temp.path();
  auto server = testing::StartServerProcess(dir + "/map.db", dir, dir + "/server.log");
  ASSERT_GT(server.port, 0) << "server did not start; see " << dir << "/server.log";
  auto stub = v1::MapService::NewStub(MakeClientChannel(server.address()));
  Register(stub.get(), "alpha", true);
  Register(stub.get(), "beta", false);
  grpc::Status status;
  EXPECT_EQ(UploadOne(stub.get(), "alpha", 0, &status).code(), 0);
  ASSERT_TRUE(testing::WaitForVersion(stub.get(), 1));
  std::string out;
  const std::string ctl = "--server " + server.address() + " ";
  EXPECT_EQ(RunCtl(ctl + "robots", &out), 0) << out;
  EXPECT_NE(out.find("UNPLACED"), std::string::npos) << out;
  EXPECT_NE(out.find("alpha"), std::string::npos) << out;
  EXPECT_EQ(RunCtl(ctl + "export --out " + dir + "/map", &out), 0) << out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/map.pgm"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/map.yaml"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/map.png"));

  grpc::ClientContext context;
  v1::VersionInfo first;
  ASSERT_TRUE(stub->GetVersion(&context, v1::GetVersionRequest(), &first).ok());
  EXPECT_EQ(UploadOne(stub.get(), "alpha", 30, &status).code(), 0);
  ASSERT_TRUE(testing::WaitForVersion(stub.get(), first.version() + 1));
  EXPECT_EQ(RunCtl(ctl + "--json history", &out), 0) << out;
  EXPECT_NE(out.find("\"versions\""), std::string::npos) << out;
  EXPECT_EQ(RunCtl(ctl + "show " + std::to_string(first.version()), &out), 0) << out;
  EXPECT_NE(out.find("placements"), std::string::npos) << out;
  EXPECT_NE(out.find("), started at ("), std::string::npos)
      << out;  // alpha, placed at registration
  EXPECT_EQ(RunCtl(ctl + "--json diff " + std::to_string(first.version()) + " " +
                       std::to_string(first.version() + 1) + " --out " + dir + "/diff.png",
                   &out),
            0) << out;
  EXPECT_NE(out.find("\"changed\": "), std::string::npos) << out;
  EXPECT_EQ(out.find("\"changed\": 0,"), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/diff.png"));
  EXPECT_NE(RunCtl(ctl + "show 9999", &out), 0);
  EXPECT_NE(out.find("NOT_FOUND"), std::string::npos) << out;
  EXPECT_EQ(testing::StopProcess(server.pid, SIGTERM), 0) << "clean shutdown on SIGTERM";
}

TEST(ServerProcessTest, RefusesDatabaseFromNewerSchema) {
  const testing::ScopedTempDir temp("e2e_schema");
  const std::string& dir = temp.path();
  const std::string db_path = dir + "/map.db";
  {
    SqliteMapStoreOptions options;
    options.path = db_path;
    std::string error;
    ASSERT_TRUE(SqliteMapStore::Open(options, &error)) << error;
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE schema_version SET version = 7", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto server = testing::StartServerProcess(db_path, dir, dir + "/server.log");
  EXPECT_EQ(server.port, 0);
  if (server.pid > 0) testing::StopProcess(server.pid, SIGKILL);
  std::ifstream log(dir + "/server.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("newer than this server"), std::string::npos) << text;
}

// SIGKILL mid-upload: every acknowledged submap survives, nothing is stored twice.
TEST(ServerProcessTest, KillNineLosesNoAcknowledgedUpload) {
  const testing::ScopedTempDir temp("e2e_kill");
  const std::string& dir = temp.path();
  const std::string db_path = dir + "/map.db";
  auto server = testing::StartServerProcess(db_path, dir, dir + "/server.log");
  ASSERT_GT(server.port, 0);
  auto stub = v1::MapService::NewStub(MakeClientChannel(server.address()));
  Register(stub.get(), "r1", true);
  std::set<int64_t> acked;
  std::atomic<int> acked_count{0};
  int64_t next_id = 0;
  std::thread uploader([&] {
    for (;; ++next_id) {
      grpc::Status status;
      const v1::ItemAck ack = UploadOne(stub.get(), "r1", next_id, &status);
      if (!status.ok()) return;  // the server is gone
      if (ack.code() == 0) {
        acked.insert(next_id);
        ++acked_count;
      }
    }
  });
  while (acked_count < 60) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_EQ(testing::StopProcess(server.pid, SIGKILL), 128 + SIGKILL);
  uploader.join();
  ASSERT_GE(acked.size(), 60u);

  // Restart on the same database; the agent's outbox would now retry everything unacked.
  server = testing::StartServerProcess(db_path, dir, dir + "/server.log");
  ASSERT_GT(server.port, 0);
  stub = v1::MapService::NewStub(MakeClientChannel(server.address()));
  for (int64_t id = 0; id <= next_id; ++id) {
    grpc::Status status;
    const v1::ItemAck ack = UploadOne(stub.get(), "r1", id, &status);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(ack.code(), 0);
    if (acked.count(id)) {
      EXPECT_TRUE(ack.duplicate()) << "acked submap " << id << " was lost";
    }
  }
  EXPECT_EQ(testing::StopProcess(server.pid, SIGTERM), 0);

  SqliteMapStoreOptions options;
  options.path = db_path;
  std::string error;
  auto store = SqliteMapStore::Open(options, &error);
  ASSERT_TRUE(store) << error;
  EXPECT_EQ(store->CountSubmapRevisions("r1"), next_id + 1) << "no duplicates, nothing lost";
  EXPECT_EQ(store->CountSubmapIds("r1"), next_id + 1);
  for (int64_t id : acked) EXPECT_TRUE(store->GetSubmap(SubmapKey{"r1", id, 0})) << id;
}

}  // namespace
}  // namespace fleetmap
