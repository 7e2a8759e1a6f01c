// Pose densities between two robots through the real server: the observed robot's exchange says
// it is listening once the server has registered it, and what the observer sends arrives once,
// intact; an unregistered robot is not listening.
#include "robot_agent/agent/density_exchange.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/agent/test_server.h"

namespace fleetmap {
namespace {

using testing::WaitFor;

void Register(MapServer& server, const std::string& id) {
  auto stub = v1::MapService::NewStub(server.InProcessChannel());
  grpc::ClientContext context;
  v1::RegisterRobotRequest request;
  request.set_robot_id(id);
  request.set_localization_only(true);
  v1::RegisterRobotResponse response;
  ASSERT_TRUE(stub->RegisterRobot(&context, request, &response).ok());
}

DensityExchangeOptions Options(const std::string& id) {
  DensityExchangeOptions options;
  options.robot_id = id;
  options.reconnect.initial = 0.02;
  options.reconnect.max = 0.1;
  return options;
}

TEST(DensityExchangeTest, WhatOneRobotSendsTheSeenRobotReceivesThroughTheServer) {
  auto server = testing::StartServer(0);
  ASSERT_NE(server, nullptr);
  const auto channel = grpc::CreateChannel("127.0.0.1:" + std::to_string(server->port()),
                                           grpc::InsecureChannelCredentials());
  DensityExchange lost(Options("lost"), channel);
  DensityExchange seer(Options("seer"), channel);
  lost.Start();
  seer.Start();
  // Not registered yet: the server refuses the subscription, and the exchange retries.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_FALSE(lost.subscribed());
  Register(*server, "lost");
  Register(*server, "seer");
  ASSERT_TRUE(WaitFor([&] { return lost.subscribed(); }, 10.0));

  PoseDensity density;
  density.observer_id = "seer";
  density.observed_id = "lost";
  density.timestamp = 42.5;
  PoseDensityKernel kernel;
  kernel.weight = 2.0;  // normalised on arrival
  kernel.mean = Eigen::Vector2d(3.0, -1.0);
  kernel.covariance << 0.01, 0.002, 0.002, 0.02;
  density.kernels.push_back(kernel);
  seer.Send(density);
  std::vector<PoseDensity> received;
  ASSERT_TRUE(WaitFor(
      [&] {
        for (PoseDensity& d : lost.TakeReceived()) received.push_back(std::move(d));
        return !received.empty();
      },
      10.0));
  ASSERT_EQ(received.size(), 1u);
  EXPECT_EQ(received[0].observer_id, "seer");
  EXPECT_DOUBLE_EQ(received[0].timestamp, 42.5);
  ASSERT_EQ(received[0].kernels.size(), 1u);
  EXPECT_DOUBLE_EQ(received[0].kernels[0].weight, 1.0);
  EXPECT_TRUE(received[0].kernels[0].mean.isApprox(kernel.mean));
  EXPECT_DOUBLE_EQ(received[0].kernels[0].covariance(0, 1), 0.002);
  EXPECT_TRUE(WaitFor([&] { return seer.stats().delivered == 1; }, 5.0));
  EXPECT_EQ(seer.stats().sent, 1);
  EXPECT_EQ(lost.stats().received, 1);

  // A density about a robot the server does not know is refused, and counted.
  density.observed_id = "ghost";
  seer.Send(density);
  EXPECT_TRUE(WaitFor([&] { return seer.stats().send_failed == 1; }, 5.0));
  lost.Stop();
  seer.Stop();
}

}  // namespace
}  // namespace fleetmap
