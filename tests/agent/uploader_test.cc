// The uploader against the real map server, in process, on loopback.
#include "robot_agent/agent/uploader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "robot_agent/agent/mapping_pipeline.h"
#include "robot_agent/agent/proto_conversions.h"
#include "tests/agent/test_server.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using testing::QueueSubmaps;

UploaderOptions FastOptions() {
  UploaderOptions options;
  options.backoff.initial = 0.02;
  options.backoff.max = 0.2;
  options.rpc_timeout = 5.0;
  options.max_batch_items = 4;
  return options;
}

v1::RegisterRobotRequest Registration(const std::string& robot_id) {
  v1::RegisterRobotRequest request;
  request.set_robot_id(robot_id);
  request.set_name("test robot");
  request.set_algorithm("scan-matching");
  *request.mutable_local_in_global() = agent::ToProto(Rigid2d(1.0, 2.0, 0.0));
  return request;
}

std::shared_ptr<grpc::Channel> Channel(int port) {
  return grpc::CreateChannel("127.0.0.1:" + std::to_string(port),
                             grpc::InsecureChannelCredentials());
}

class UploaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    outbox_ = Outbox::Open(dir_.path() + "/outbox.db", &error);
    ASSERT_NE(outbox_, nullptr) << error;
    server_ = testing::StartServer(0);
    ASSERT_NE(server_, nullptr);
  }
  void Enqueue(const OutboxKey& key, const std::string& payload) {
    bool inserted = false;
    std::string error;
    ASSERT_TRUE(outbox_->Enqueue(key, payload, 0.0, true, &inserted, &error)) << error;
  }
  const testing::ScopedTempDir dir_{"uploader"};  // outlives the outbox below
  std::unique_ptr<Outbox> outbox_;
  std::unique_ptr<MapServer> server_;
};

TEST_F(UploaderTest, DeliversEveryKindAndEmptiesTheOutbox) {
  QueueSubmaps(outbox_.get(), "r1", 0, 10);
  Trajectory trajectory = {{1.0, Rigid2d(0, 0, 0)}, {2.0, Rigid2d(1, 0, 0)}};
  Enqueue({"r1", OutboxKind::kTrajectory, 0, 2},
          agent::ToTrajectoryRequest("r1", 2, trajectory).SerializeAsString());
  RobotDetection detection;
  detection.observed_id = "r2";
  detection.timestamp = 1.5;
  detection.position_in_observer = {1.0, 0.0};
  detection.covariance = Eigen::Matrix2d::Identity() * 0.01;
  Enqueue({"r1", OutboxKind::kDetection, 7, 0}, agent::ToProto(detection, 7).SerializeAsString());

  Uploader uploader(FastOptions(), outbox_.get(), Channel(server_->port()), Registration("r1"));
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  const UploaderStats stats = uploader.stats();
  uploader.Stop();

  EXPECT_TRUE(stats.registered);
  EXPECT_EQ(stats.state, ConnectionState::kConnected);
  EXPECT_EQ(stats.acked_submaps, 10);
  EXPECT_EQ(stats.acked_trajectories, 1);
  EXPECT_EQ(stats.acked_detections, 1);
  EXPECT_EQ(stats.duplicates, 0);
  EXPECT_EQ(stats.rejected, 0) << stats.last_error;
  MapStore* store = server_->store();
  EXPECT_EQ(store->CountSubmapIds("r1"), 10);
  EXPECT_EQ(store->CountSubmapRevisions("r1"), 10);
  ASSERT_TRUE(store->LatestTrajectory("r1").has_value());
  EXPECT_EQ(store->LatestTrajectory("r1")->revision, 2);
  EXPECT_EQ(store->LatestTrajectory("r1")->poses.size(), 2u);
  const auto detections = store->DetectionsAfter(0);
  ASSERT_EQ(detections.size(), 1u);
  EXPECT_EQ(detections[0].detection_id, 7);
  EXPECT_EQ(detections[0].detection.observed_id, "r2");
}

TEST_F(UploaderTest, LostAcknowledgementsDuplicateNothing) {
  testing::LossyProxy proxy(server_->InProcessChannel(), /*lose_acks=*/3);
  QueueSubmaps(outbox_.get(), "r1", 0, 12);
  Uploader uploader(FastOptions(), outbox_.get(), Channel(proxy.port()), Registration("r1"));
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  const UploaderStats stats = uploader.stats();
  uploader.Stop();
  EXPECT_EQ(proxy.lost_acks(), 3);
  // Three calls of up to four items were stored but not acknowledged (a retry can be lost
  // again): sent again, acknowledged as duplicates, stored once.
  EXPECT_GE(stats.duplicates, 4);
  EXPECT_LE(stats.duplicates, 12);
  EXPECT_EQ(stats.acked_submaps, 12);
  EXPECT_EQ(server_->store()->CountSubmapRevisions("r1"), 12);
  EXPECT_EQ(server_->store()->CountSubmapIds("r1"), 12);
}

TEST_F(UploaderTest, RefusedItemsAreSetAsideAndTheRestDelivered) {
  QueueSubmaps(outbox_.get(), "r1", 0, 2);
  v1::SubmapUpload bad = agent::ToProto(testing::MakeSubmap("r1", 2, 1));
  bad.mutable_grid()->set_cells_zstd("not zstd at all");
  Enqueue({"r1", OutboxKind::kSubmap, 2, 1}, bad.SerializeAsString());
  QueueSubmaps(outbox_.get(), "r1", 3, 2);
  Enqueue({"r1", OutboxKind::kSubmap, 9, 0}, "\xff\xff garbage payload");

  Uploader uploader(FastOptions(), outbox_.get(), Channel(server_->port()), Registration("r1"));
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  const UploaderStats stats = uploader.stats();
  uploader.Stop();
  EXPECT_EQ(stats.acked_submaps, 4);
  EXPECT_EQ(stats.rejected, 2);
  EXPECT_EQ(server_->store()->CountSubmapIds("r1"), 4);
  std::vector<OutboxItem> rejected;
  std::string error;
  ASSERT_TRUE(outbox_->Rejected(&rejected, &error));
  ASSERT_EQ(rejected.size(), 2u);
  EXPECT_EQ(rejected[0].key.id, 2);
  EXPECT_THAT(rejected[0].last_error, ::testing::Not(::testing::IsEmpty()));
  EXPECT_EQ(rejected[1].key.id, 9);
}

TEST_F(UploaderTest, OlderRevisionsThanTheServerHoldsAreDroppedAsSuperseded) {
  // The server already holds revision 5 of submap 0 and trajectory revision 10 (e.g. from
  // before the agent restarted and replayed its data).
  {
    std::unique_ptr<Outbox> other = Outbox::Open(dir_.path() + "/other.db", nullptr);
    ASSERT_NE(other, nullptr);
    bool inserted;
    other->Enqueue({"r1", OutboxKind::kSubmap, 0, 5}, testing::SubmapPayload("r1", 0, 5), 0.0, true,
                   &inserted, nullptr);
    other->Enqueue({"r1", OutboxKind::kTrajectory, 0, 10},
                   agent::ToTrajectoryRequest("r1", 10, {{1.0, Rigid2d()}}).SerializeAsString(),
                   0.0, true, &inserted, nullptr);
    Uploader first(FastOptions(), other.get(), Channel(server_->port()), Registration("r1"));
    first.Start();
    ASSERT_TRUE(first.WaitUntilEmpty(20.0));
  }
  Enqueue({"r1", OutboxKind::kSubmap, 0, 3}, testing::SubmapPayload("r1", 0, 3));
  Enqueue({"r1", OutboxKind::kTrajectory, 0, 4},
          agent::ToTrajectoryRequest("r1", 4, {{1.0, Rigid2d()}}).SerializeAsString());
  Uploader uploader(FastOptions(), outbox_.get(), Channel(server_->port()), Registration("r1"));
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  const UploaderStats stats = uploader.stats();
  uploader.Stop();
  EXPECT_EQ(stats.superseded, 2);
  EXPECT_EQ(stats.rejected, 0);
  EXPECT_EQ(server_->store()->LatestTrajectory("r1")->revision, 10);
}

TEST_F(UploaderTest, AgentRestartMidUploadLosesAndDuplicatesNothing) {
  const std::string path = outbox_->path();
  QueueSubmaps(outbox_.get(), "r1", 0, 40);
  {
    UploaderOptions options = FastOptions();
    options.max_batch_items = 1;
    Uploader uploader(options, outbox_.get(), Channel(server_->port()), Registration("r1"));
    uploader.Start();
    // Stop as soon as some, not all, went out.
    for (int i = 0; i < 2000 && uploader.stats().acked_submaps < 5; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    uploader.Stop();
  }
  outbox_.reset();  // the agent process ends
  std::string error;
  outbox_ = Outbox::Open(path, &error);
  ASSERT_NE(outbox_, nullptr) << error;
  OutboxCounts counts;
  ASSERT_TRUE(outbox_->Counts(&counts, &error));
  const int64_t stored_before = server_->store()->CountSubmapIds("r1");
  EXPECT_GE(stored_before, 5);
  // Every item is stored, or still queued (or both, when the stop cut off an acknowledgement).
  EXPECT_GE(counts.pending + stored_before, 40);
  Uploader uploader(FastOptions(), outbox_.get(), Channel(server_->port()), Registration("r1"));
  uploader.Start();
  ASSERT_TRUE(uploader.WaitUntilEmpty(20.0));
  uploader.Stop();
  EXPECT_EQ(server_->store()->CountSubmapIds("r1"), 40);
  EXPECT_EQ(server_->store()->CountSubmapRevisions("r1"), 40);
}

}  // namespace
}  // namespace fleetmap
