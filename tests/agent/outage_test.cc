// The server goes away and comes back: the outbox grows, then drains; nothing is lost and
// nothing is stored twice. Also a server restart on its SQLite database mid-run.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "robot_agent/agent/proto_conversions.h"
#include "robot_agent/agent/uploader.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::QueueSubmaps;

UploaderOptions FastOptions() {
  UploaderOptions options;
  options.backoff.initial = 0.02;
  options.backoff.max = 0.2;
  options.rpc_timeout = 2.0;
  options.max_batch_items = 8;
  return options;
}

v1::RegisterRobotRequest Registration() {
  v1::RegisterRobotRequest request;
  request.set_robot_id("r1");
  *request.mutable_local_in_global() = agent::ToProto(Rigid2d());
  return request;
}

std::shared_ptr<grpc::Channel> Channel(int port) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
  args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 200);
  return grpc::CreateCustomChannel("127.0.0.1:" + std::to_string(port),
                                   grpc::InsecureChannelCredentials(), args);
}

int64_t Pending(Outbox* outbox) {
  OutboxCounts counts;
  std::string error;
  EXPECT_TRUE(outbox->Counts(&counts, &error)) << error;
  return counts.pending;
}

TEST(OutageTest, OutboxGrowsWhileTheServerIsAwayThenDrains) {
  const testing::ScopedTempDir temp("outage");
  const std::string& dir = temp.path();
  const std::string db = dir + "/server.db";
  std::string error;
  auto outbox = Outbox::Open(dir + "/outbox.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  auto server = testing::StartServer(0, db);
  ASSERT_NE(server, nullptr);
  const int port = server->port();

  Uploader uploader(FastOptions(), outbox.get(), Channel(port), Registration());
  uploader.Start();
  QueueSubmaps(outbox.get(), "r1", 0, 10);
  uploader.Notify();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  EXPECT_EQ(server->store()->CountSubmapIds("r1"), 10);

  // Outage: the server goes down; the robot keeps mapping.
  server->Shutdown(0.5);
  server.reset();
  for (int batch = 0; batch < 5; ++batch) {
    QueueSubmaps(outbox.get(), "r1", 10 + 6 * batch, 6);
    uploader.Notify();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_EQ(Pending(outbox.get()), 30) << "the outbox holds everything made during the outage";
  const UploaderStats during = uploader.stats();
  EXPECT_EQ(during.state, ConnectionState::kDisconnected);
  EXPECT_GT(during.failed_calls, 0);

  // The server comes back on the same address with its database.
  server = testing::RestartServer(port, db);
  ASSERT_NE(server, nullptr);
  ASSERT_TRUE(uploader.WaitUntilEmpty(30.0)) << uploader.stats().last_error;
  const UploaderStats after = uploader.stats();
  uploader.Stop();
  EXPECT_EQ(after.state, ConnectionState::kConnected);
  EXPECT_EQ(after.acked_submaps, 40);
  EXPECT_EQ(after.rejected, 0);
  EXPECT_EQ(server->store()->CountSubmapIds("r1"), 40) << "nothing lost";
  EXPECT_EQ(server->store()->CountSubmapRevisions("r1"), 40) << "nothing duplicated";
}

TEST(OutageTest, ServerLosingItsDatabaseGetsTheRobotRegisteredAgain) {
  const testing::ScopedTempDir temp("outage");
  const std::string& dir = temp.path();
  std::string error;
  auto outbox = Outbox::Open(dir + "/outbox.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  auto server = testing::StartServer(0);  // in memory: a restart forgets everything
  ASSERT_NE(server, nullptr);
  const int port = server->port();
  Uploader uploader(FastOptions(), outbox.get(), Channel(port), Registration());
  uploader.Start();
  QueueSubmaps(outbox.get(), "r1", 0, 3);
  uploader.Notify();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  server->Shutdown(0.5);
  server.reset();
  server = testing::RestartServer(port, "");
  ASSERT_NE(server, nullptr);
  QueueSubmaps(outbox.get(), "r1", 3, 3);
  uploader.Notify();
  ASSERT_TRUE(uploader.WaitUntilEmpty(30.0)) << uploader.stats().last_error;
  uploader.Stop();
  // The new server answered NOT_FOUND until the robot registered again.
  ASSERT_TRUE(server->store()->GetRobot("r1").has_value());
  EXPECT_EQ(server->store()->CountSubmapIds("r1"), 3);
}

}  // namespace
}  // namespace fleetmap
