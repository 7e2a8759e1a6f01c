// The subscription to the global map against the real server: versions arrive with their grid
// and the robots' placements, and the stream is resumed after the server restarts.
#include "robot_agent/agent/map_subscriber.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "robot_agent/agent/proto_conversions.h"
#include "robot_agent/agent/uploader.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

std::shared_ptr<grpc::Channel> Channel(int port) {
  grpc::ChannelArguments args;
  args.SetInt(GRPC_ARG_INITIAL_RECONNECT_BACKOFF_MS, 100);
  args.SetInt(GRPC_ARG_MIN_RECONNECT_BACKOFF_MS, 100);
  args.SetInt(GRPC_ARG_MAX_RECONNECT_BACKOFF_MS, 200);
  args.SetMaxReceiveMessageSize(64 << 20);
  return grpc::CreateCustomChannel("127.0.0.1:" + std::to_string(port),
                                   grpc::InsecureChannelCredentials(), args);
}

using testing::WaitFor;

void Upload(int port, Outbox* outbox, int64_t first_id, int count) {
  v1::RegisterRobotRequest registration;
  registration.set_robot_id("r1");
  *registration.mutable_local_in_global() = agent::ToProto(Rigid2d(1.0, 2.0, 0.0));
  UploaderOptions options;
  options.backoff.max = 0.2;
  Uploader uploader(options, outbox, Channel(port), registration);
  testing::QueueSubmaps(outbox, "r1", first_id, count);
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0)) << uploader.stats().last_error;
}

TEST(MapSubscriberTest, FollowsVersionsAndResumesAfterAServerRestart) {
  const testing::ScopedTempDir temp("subscriber");
  const std::string& dir = temp.path();
  const std::string db = dir + "/server.db";
  std::string error;
  auto outbox = Outbox::Open(dir + "/outbox.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  auto server = testing::StartServer(0, db);
  ASSERT_NE(server, nullptr);
  const int port = server->port();

  MapSubscriberOptions options;
  options.reconnect.initial = 0.05;
  options.reconnect.max = 0.2;
  options.file = dir + "/global";
  MapSubscriber subscriber(options, Channel(port));
  subscriber.Start();

  Upload(port, outbox.get(), 0, 2);
  ASSERT_TRUE(WaitFor(
      [&] {
        auto map = subscriber.latest();
        return map && map->has_grid && !map->robots.empty() && map->robots[0].placed;
      },
      20.0))
      << subscriber.last_error();
  auto first = subscriber.latest();
  EXPECT_GE(first->version, 1);
  EXPECT_GT(first->grid.geometry.width, 0);
  EXPECT_EQ(first->robots[0].robot_id, "r1");
  EXPECT_NEAR(first->robots[0].local_in_global.x(), 1.0, 1e-9);
  EXPECT_NEAR(first->robots[0].local_in_global.y(), 2.0, 1e-9);
  EXPECT_TRUE(subscriber.streaming());
  EXPECT_TRUE(WaitFor([&] { return std::ifstream(dir + "/global.pgm").good(); }, 5.0));

  // The server restarts: the stream breaks, the subscriber reconnects and picks up what
  // follows.
  server->Shutdown(0.5);
  server.reset();
  ASSERT_TRUE(WaitFor([&] { return !subscriber.streaming(); }, 10.0));
  server = testing::RestartServer(port, db);
  ASSERT_NE(server, nullptr);
  Upload(port, outbox.get(), 2, 3);
  ASSERT_TRUE(WaitFor(
      [&] {
        auto map = subscriber.latest();
        return map && map->version > first->version;
      },
      20.0))
      << subscriber.last_error();
  EXPECT_GE(subscriber.reconnects(), 1);
  EXPECT_TRUE(subscriber.latest()->has_grid);
  subscriber.Stop();
  EXPECT_FALSE(subscriber.streaming());
}

TEST(MapSubscriberTest, StopsPromptlyWhenNoServerIsThere) {
  // Nothing listens on this port (the OS gave it to a server that is gone).
  int port;
  {
    auto server = testing::StartServer(0);
    ASSERT_NE(server, nullptr);
    port = server->port();
  }
  MapSubscriber subscriber(MapSubscriberOptions(), Channel(port));
  subscriber.Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(subscriber.streaming());
  EXPECT_EQ(subscriber.latest(), nullptr);
  subscriber.Stop();  // must not hang (the test's timeout would catch it)
}

}  // namespace
}  // namespace fleetmap
