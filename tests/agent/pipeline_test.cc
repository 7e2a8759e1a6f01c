#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <set>

#include "proto/fleetmap/v1/fleetmap.pb.h"
#include "robot_agent/agent/mapping_pipeline.h"
#include "robot_agent/agent/slam_factory.h"
#include "tests/agent/synthetic_drive.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

std::unique_ptr<MappingPipeline> MakePipeline(Outbox* outbox, int* notifications,
                                              double laser_body_radius = 0.0) {
  SlamConfig slam;
  slam.submap_scans = 30;
  std::string error;
  auto backend = CreateLocalSlam(slam, "r1", &error);
  EXPECT_NE(backend, nullptr) << error;
  MappingPipelineOptions options;
  options.robot_id = "r1";
  options.trajectory_period = 5.0;
  options.laser_body_radius = laser_body_radius;
  return std::make_unique<MappingPipeline>(
      options, std::move(backend), outbox, [] { return 1.0; },
      [notifications] { ++*notifications; });
}

std::vector<OutboxItem> All(Outbox* outbox, OutboxKind kind) {
  std::vector<OutboxItem> items;
  std::string error;
  EXPECT_TRUE(outbox->Due(kind, 1e18, 100000, 1LL << 40, &items, &error)) << error;
  return items;
}

TEST(MappingPipelineTest, QueuesFinishedSubmapsAndTrajectoryRevisions) {
  const testing::ScopedTempDir dir("pipeline");
  std::string error;
  auto outbox = Outbox::Open(dir.path() + "/o.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  int notifications = 0;
  auto pipeline = MakePipeline(outbox.get(), &notifications);
  const auto events = testing::SyntheticDrive(200);
  for (const SensorEvent& event : events) ASSERT_TRUE(pipeline->Process(event, &error)) << error;
  ASSERT_TRUE(pipeline->Finish(&error)) << error;

  EXPECT_EQ(pipeline->counters().scans, 200);
  EXPECT_EQ(pipeline->counters().refused_inputs, 0) << pipeline->last_refusal();
  const auto submaps = All(outbox.get(), OutboxKind::kSubmap);
  ASSERT_GE(submaps.size(), 2u);
  std::set<int64_t> ids;
  for (const OutboxItem& item : submaps) {
    v1::SubmapUpload upload;
    ASSERT_TRUE(upload.ParseFromString(item.payload));
    EXPECT_EQ(upload.submap_id(), item.key.id);
    EXPECT_EQ(upload.revision(), item.key.revision);
    EXPECT_TRUE(upload.finished());
    EXPECT_GT(upload.grid().width(), 10);
    EXPECT_FALSE(upload.grid().cells_zstd().empty());
    EXPECT_GT(upload.scan_poses_size(), 0);
    ids.insert(item.key.id);
  }
  // Consecutive ids from 0.
  EXPECT_EQ(*ids.begin(), 0);
  EXPECT_EQ(*ids.rbegin(), static_cast<int64_t>(ids.size()) - 1);

  // 20 s of data, a revision every 5 s, superseded in the outbox by the newest: one pending,
  // with one pose per scan, close to the truth (exact odometry, exact scans).
  EXPECT_GE(pipeline->counters().trajectories_queued, 4);
  const auto trajectories = All(outbox.get(), OutboxKind::kTrajectory);
  ASSERT_EQ(trajectories.size(), 1u);
  v1::UploadTrajectoryRequest trajectory;
  ASSERT_TRUE(trajectory.ParseFromString(trajectories[0].payload));
  ASSERT_EQ(trajectory.poses_size(), 200);
  // The newest revision: whatever the backend's revision, it holds all 200 poses.
  EXPECT_EQ(trajectory.revision() & 0xffffffffLL, 200);
  EXPECT_EQ(trajectory.revision(), MappingPipeline::TrajectoryRevision(
                                       trajectory.revision() >> 32, 200));
  const auto& last = trajectory.poses(199);
  const Rigid2d truth = *events.back().ground_truth;
  EXPECT_NEAR(last.pose().x(), truth.x(), 0.05);
  EXPECT_NEAR(last.pose().y(), truth.y(), 0.05);
  EXPECT_GT(notifications, 0);
}

TEST(MappingPipelineTest, ReplayingTheSameDataQueuesNothingNew) {
  const testing::ScopedTempDir dir("pipeline");
  std::string error;
  auto outbox = Outbox::Open(dir.path() + "/o.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  const auto events = testing::SyntheticDrive(120);
  std::vector<OutboxItem> first;
  for (int run = 0; run < 2; ++run) {
    int notifications = 0;
    auto pipeline = MakePipeline(outbox.get(), &notifications);
    for (const SensorEvent& event : events) ASSERT_TRUE(pipeline->Process(event, &error));
    ASSERT_TRUE(pipeline->Finish(&error));
    auto items = All(outbox.get(), OutboxKind::kSubmap);
    const auto trajectories = All(outbox.get(), OutboxKind::kTrajectory);
    items.insert(items.end(), trajectories.begin(), trajectories.end());
    if (run == 0) {
      first = items;
      continue;
    }
    // The restarted agent produced the same keys: the outbox holds the same items.
    ASSERT_EQ(items.size(), first.size());
    for (size_t i = 0; i < items.size(); ++i) {
      EXPECT_EQ(items[i].seq, first[i].seq);
      EXPECT_EQ(items[i].key.id, first[i].key.id);
      EXPECT_EQ(items[i].key.revision, first[i].key.revision);
    }
  }
}

// A round body of the robots' radius drives across the room at 0.5 m/s: asked to, the pipeline
// masks its returns. The same body standing still (a pillar) is found but stays in the map.
TEST(MappingPipelineTest, MasksRoundBodiesTheLaserFindsWhenAsked) {
  for (const bool moving : {true, false}) {
    SCOPED_TRACE(moving ? "moving body" : "fixed body");
    std::vector<SensorEvent> events = testing::SyntheticDrive(90);
    const double start = events.front().timestamp;
    int on_other = 0;
    for (SensorEvent& event : events) {
      if (!event.laser) continue;
      const double t = event.laser->scan.timestamp;
      const Eigen::Vector2d other(4.5 - (moving ? 0.5 * (t - start) : 0.0), 1.5);
      testing::SegmentWorld world = testing::SyntheticRoom();
      testing::AddCylinder(other, 0.2, &world);
      event.laser->scan = testing::SimulateScan(world, *event.ground_truth);
      event.laser->scan.timestamp = t;
      const Eigen::Vector2d seen = event.ground_truth->inverse() * other;
      for (int i = 0; i < event.laser->scan.size(); ++i) {
        const double r = event.laser->scan.ranges[static_cast<size_t>(i)];
        const double a = event.laser->scan.angle(i);
        on_other += event.laser->scan.IsReturn(i) &&
                    (Eigen::Vector2d(r * std::cos(a), r * std::sin(a)) - seen).norm() < 0.25;
      }
    }
    ASSERT_GT(on_other, 200);
    for (const double radius : {0.0, 0.2}) {
      const testing::ScopedTempDir dir("pipeline");
      std::string error;
      auto outbox = Outbox::Open(dir.path() + "/o.db", &error);
      ASSERT_NE(outbox, nullptr) << error;
      int notifications = 0;
      auto pipeline = MakePipeline(outbox.get(), &notifications, radius);
      for (const SensorEvent& event : events) ASSERT_TRUE(pipeline->Process(event, &error)) << error;
      ASSERT_TRUE(pipeline->Finish(&error)) << error;
      if (radius == 0.0) {
        EXPECT_EQ(pipeline->counters().laser_bodies, 0);
        EXPECT_EQ(pipeline->counters().masked_returns, 0);
      } else if (moving) {
        EXPECT_GT(pipeline->counters().laser_bodies, 20);
        // Every return off it, in the scans where it showed enough of itself, and little else.
        EXPECT_GT(pipeline->counters().masked_returns, on_other * 7 / 10);
        EXPECT_LT(pipeline->counters().masked_returns, on_other * 13 / 10);
      } else {
        EXPECT_GT(pipeline->counters().laser_bodies, 30);
        EXPECT_EQ(pipeline->counters().masked_returns, 0);
      }
    }
  }
}

TEST(MappingPipelineTest, DetectionsGetDeterministicIds) {
  const testing::ScopedTempDir dir("pipeline");
  std::string error;
  auto outbox = Outbox::Open(dir.path() + "/o.db", &error);
  ASSERT_NE(outbox, nullptr) << error;
  int notifications = 0;
  auto pipeline = MakePipeline(outbox.get(), &notifications);
  RobotDetection a;
  a.observer_id = "r1";
  a.observed_id = "r2";
  a.timestamp = 1234.5678;
  a.position_in_observer = {2.0, 0.5};
  RobotDetection b = a;
  b.observed_id = "r3";
  ASSERT_TRUE(pipeline->AddDetections({a, b, a}, &error)) << error;
  const auto items = All(outbox.get(), OutboxKind::kDetection);
  ASSERT_EQ(items.size(), 2u);  // the repeated one is the same item
  EXPECT_EQ(items[0].key.id, MappingPipeline::DetectionId(a));
  EXPECT_NE(items[0].key.id, items[1].key.id);
  v1::Detection detection;
  ASSERT_TRUE(detection.ParseFromString(items[0].payload));
  EXPECT_EQ(detection.observed_id(), "r2");
  EXPECT_DOUBLE_EQ(detection.x(), 2.0);
}

}  // namespace
}  // namespace fleetmap
