// The live simulated robot as a sensor source, through the mapping pipeline: the robot's local
// SLAM trajectory must follow the simulator's ground truth.
#include "robot_agent/agent/sim_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>

#include "robot_agent/agent/mapping_pipeline.h"
#include "robot_agent/agent/slam_factory.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(SimSourceTest, UnknownRobotAndScenarioAreClearErrors) {
  std::string error;
  EXPECT_EQ(SimSource::Open("department_3robots", "robot9", false, &error), nullptr);
  EXPECT_THAT(error, ::testing::HasSubstr("no robot 'robot9'"));
  EXPECT_THAT(error, ::testing::HasSubstr("robot1"));
  EXPECT_EQ(SimSource::Open("no_such_scenario", "robot1", false, &error), nullptr);
  EXPECT_THAT(error, ::testing::HasSubstr("source.simulator.scenario"));
}

TEST(SimSourceTest, LocalSlamOnASimulatedRobotFollowsTheGroundTruth) {
  SourceConfig config;
  config.type = SourceConfig::Type::kSimulator;
  config.scenario = "department_3robots";
  config.sim_robot = "robot2";
  std::string error;
  std::unique_ptr<SensorSource> source = OpenSensorSource(config, &error);
  ASSERT_NE(source, nullptr) << error;
  EXPECT_EQ(source->Describe(), "simulator department_3robots, robot robot2");

  const testing::ScopedTempDir dir("sim_source");
  auto outbox = Outbox::Open(dir.path() + "/o.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  auto slam = CreateLocalSlam(SlamConfig(), "robot2", &error);
  ASSERT_NE(slam, nullptr) << error;
  MappingPipelineOptions options;
  options.robot_id = "robot2";
  MappingPipeline pipeline(options, std::move(slam), outbox.get(), [] { return 0.0; });

  SensorEvent event;
  std::optional<Rigid2d> first_truth;
  Rigid2d last_truth;
  std::optional<Rigid2d> first_odometry;
  Rigid2d last_odometry;
  double path_length = 0.0;
  double last_time = -1e9;
  while (source->Next(&event)) {
    ASSERT_GE(event.timestamp, last_time) << "events come in time order";
    last_time = event.timestamp;
    if (event.laser) {
      ASSERT_TRUE(event.ground_truth.has_value());
      if (!first_truth) {
        first_truth = *event.ground_truth;
        first_odometry = event.laser->robot_pose;
      } else {
        path_length += (event.ground_truth->translation() - last_truth.translation()).norm();
      }
      last_truth = *event.ground_truth;
      last_odometry = event.laser->robot_pose;
    }
    ASSERT_TRUE(pipeline.Process(event, &error)) << error;
  }
  EXPECT_TRUE(source->error().empty()) << source->error();
  ASSERT_TRUE(pipeline.Finish(&error)) << error;
  ASSERT_GT(pipeline.counters().scans, 500);
  // The local map frame is the first scan's pose: compare the end pose relative to the start.
  const Rigid2d truth = first_truth->inverse() * last_truth;
  const Rigid2d estimate = pipeline.slam().CurrentPose();
  const Rigid2d odometry = first_odometry->inverse() * last_odometry;
  const double slam_error = (truth.translation() - estimate.translation()).norm();
  const double odometry_error = (truth.translation() - odometry.translation()).norm();
  std::printf(
      "sim robot2: %lld scans, %.1f m driven, end-point error: SLAM %.3f m (%.2f deg), "
      "odometry %.3f m\n",
      static_cast<long long>(pipeline.counters().scans.load()), path_length, slam_error,
      std::abs(NormalizeAngle(truth.rotation() - estimate.rotation())) * 180 / M_PI,
      odometry_error);
  // The agent wires the source to the backend correctly when SLAM beats raw odometry and
  // stays within a few percent of the distance driven (the backend's own accuracy is issue
  // 4's to test).
  EXPECT_LT(slam_error, odometry_error);
  EXPECT_LT(slam_error, 0.1 * path_length);
  EXPECT_LT(std::abs(NormalizeAngle(truth.rotation() - estimate.rotation())), 0.1);
  OutboxCounts counts;
  ASSERT_TRUE(outbox->Counts(&counts, &error));
  EXPECT_GE(counts.pending_submaps, 2);
}

}  // namespace
}  // namespace fleetmap
