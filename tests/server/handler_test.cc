// The handlers against the in-memory store, called directly (no network).
#include <gtest/gtest.h>

#include "map_server/server/known_pose_merge_worker.h"
#include "map_server/server/map_service.h"
#include "map_server/store/memory_map_store.h"
#include "tests/server/server_test_util.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using grpc::StatusCode;

class HandlerTest : public ::testing::Test {
 protected:
  HandlerTest() : worker_(WorkerOptions(), &store_, &feed_), service_({}, &store_, &worker_, &feed_) {
    worker_.Start();
  }
  ~HandlerTest() override { worker_.Stop(); }
  static KnownPoseMergeWorkerOptions WorkerOptions() {
    KnownPoseMergeWorkerOptions options;
    options.min_version_interval = 0.0;
    return options;
  }
  grpc::Status Register(const std::string& id, bool with_pose, const Rigid2d& pose = Rigid2d()) {
    grpc::ServerContext context;
    v1::RegisterRobotResponse response;
    auto request = testing::MakeRegistration(id, with_pose, pose);
    return service_.RegisterRobot(&context, &request, &response);
  }
  v1::UploadSubmapsResponse Upload(const std::string& robot, const v1::SubmapUpload& upload,
                                   grpc::Status* status = nullptr) {
    grpc::ServerContext context;
    v1::UploadSubmapsRequest request;
    request.set_robot_id(robot);
    *request.add_submaps() = upload;
    v1::UploadSubmapsResponse response;
    const grpc::Status s = service_.UploadSubmaps(&context, &request, &response);
    if (status) *status = s;
    return response;
  }
  // Waits until the worker published a version covering every stored submap.
  std::shared_ptr<const GlobalMapSnapshot> WaitCovered() {
    for (int i = 0; i < 500; ++i) {
      auto latest = feed_.Latest();
      if (latest && latest->info.covered_submap_seq >= store_.MaxSubmapSeq()) return latest;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return nullptr;
  }

  MemoryMapStore store_;
  VersionFeed feed_;
  KnownPoseMergeWorker worker_;
  MapServiceImpl service_;
};

TEST_F(HandlerTest, RegisterValidatesIds) {
  EXPECT_TRUE(Register("robot_1", true).ok());
  EXPECT_EQ(Register("", true).error_code(), StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(Register("bad id!", true).error_code(), StatusCode::INVALID_ARGUMENT);
}

TEST_F(HandlerTest, UploadIsIdempotentAndRefusesOldRevisions) {
  ASSERT_TRUE(Register("r1", true).ok());
  auto ack = Upload("r1", testing::MakeSubmapUpload(0, 1)).acks(0);
  EXPECT_EQ(ack.code(), 0);
  EXPECT_FALSE(ack.duplicate());
  ack = Upload("r1", testing::MakeSubmapUpload(0, 1)).acks(0);
  EXPECT_EQ(ack.code(), 0);
  EXPECT_TRUE(ack.duplicate());
  ack = Upload("r1", testing::MakeSubmapUpload(0, 0)).acks(0);
  EXPECT_EQ(ack.code(), static_cast<int>(StatusCode::FAILED_PRECONDITION));
  EXPECT_EQ(store_.CountSubmapRevisions("r1"), 1);
}

TEST_F(HandlerTest, UnknownRobotIsNotFound) {
  grpc::Status status;
  Upload("ghost", testing::MakeSubmapUpload(0, 0), &status);
  EXPECT_EQ(status.error_code(), StatusCode::NOT_FOUND);
  grpc::ServerContext context;
  v1::UploadTrajectoryRequest request;
  request.set_robot_id("ghost");
  v1::UploadTrajectoryResponse response;
  EXPECT_EQ(service_.UploadTrajectory(&context, &request, &response).error_code(),
            StatusCode::NOT_FOUND);
}

TEST_F(HandlerTest, CorruptAndAbsurdGridsAreRefusedPerItem) {
  ASSERT_TRUE(Register("r1", true).ok());
  v1::SubmapUpload corrupt = testing::MakeSubmapUpload(0, 0);
  corrupt.mutable_grid()->set_cells_zstd("\x28\xb5\x2f\xfd garbage");
  EXPECT_EQ(Upload("r1", corrupt).acks(0).code(), static_cast<int>(StatusCode::INVALID_ARGUMENT));
  v1::SubmapUpload huge = testing::MakeSubmapUpload(1, 0);
  huge.mutable_grid()->set_width(2000000000);
  huge.mutable_grid()->set_height(2000000000);
  EXPECT_EQ(Upload("r1", huge).acks(0).code(), static_cast<int>(StatusCode::RESOURCE_EXHAUSTED));
  v1::SubmapUpload nan_pose = testing::MakeSubmapUpload(2, 0);
  nan_pose.mutable_submap_in_local()->set_x(std::nan(""));
  EXPECT_EQ(Upload("r1", nan_pose).acks(0).code(), static_cast<int>(StatusCode::INVALID_ARGUMENT));
  EXPECT_EQ(store_.CountSubmapRevisions("r1"), 0);
}

TEST_F(HandlerTest, TooManyItemsIsResourceExhausted) {
  ASSERT_TRUE(Register("r1", true).ok());
  grpc::ServerContext context;
  v1::UploadSubmapsRequest request;
  request.set_robot_id("r1");
  for (int i = 0; i < 300; ++i) *request.add_submaps() = v1::SubmapUpload();
  v1::UploadSubmapsResponse response;
  EXPECT_EQ(service_.UploadSubmaps(&context, &request, &response).error_code(),
            StatusCode::RESOURCE_EXHAUSTED);
}

TEST_F(HandlerTest, DetectionsValidateCovariance) {
  ASSERT_TRUE(Register("r1", true).ok());
  grpc::ServerContext context;
  v1::ReportDetectionsRequest request;
  request.set_observer_id("r1");
  v1::Detection* good = request.add_detections();
  good->set_detection_id(1);
  good->set_observed_id("r2");
  good->set_x(2.0);
  good->set_cov_xx(0.01);
  good->set_cov_yy(0.01);
  good->set_confidence(0.9);
  v1::Detection* bad = request.add_detections();
  *bad = *good;
  bad->set_detection_id(2);
  bad->set_cov_xx(-1.0);
  v1::ReportDetectionsResponse response;
  ASSERT_TRUE(service_.ReportDetections(&context, &request, &response).ok());
  EXPECT_EQ(response.acks(0).code(), 0);
  EXPECT_EQ(response.acks(1).code(), static_cast<int>(StatusCode::INVALID_ARGUMENT));
}

TEST_F(HandlerTest, GlobalMapPlacesKnownRobotsOnly) {
  ASSERT_TRUE(Register("placed", true, Rigid2d(5.0, 0.0, 0.0)).ok());
  ASSERT_TRUE(Register("lost", false).ok());
  EXPECT_EQ(Upload("placed", testing::MakeSubmapUpload(0, 0)).acks(0).code(), 0);
  EXPECT_EQ(Upload("lost", testing::MakeSubmapUpload(0, 0, Rigid2d(-50, 0, 0))).acks(0).code(), 0);
  const auto snapshot = WaitCovered();
  ASSERT_TRUE(snapshot);
  // Only the placed robot's 2 m x 2 m submap is in the map, at x in [5, 7].
  EXPECT_NEAR(snapshot->grid.geometry.origin.x(), 5.0, 1e-6);
  EXPECT_EQ(snapshot->grid.geometry.width, 40);
  EXPECT_DOUBLE_EQ(snapshot->info.quality.at("robots_unplaced"), 1.0);

  grpc::ServerContext context;
  v1::GetRobotsRequest request;
  v1::GetRobotsResponse robots;
  ASSERT_TRUE(service_.GetRobots(&context, &request, &robots).ok());
  ASSERT_EQ(robots.robots_size(), 2);
  EXPECT_FALSE(robots.robots(0).placement().placed());  // "lost" sorts first
  EXPECT_NE(robots.robots(0).placement().note().find("merge engine"), std::string::npos);
  EXPECT_TRUE(robots.robots(1).placement().placed());

  v1::GetGlobalMapRequest map_request;
  map_request.set_version(snapshot->info.version + 100);
  v1::GlobalMap map;
  grpc::ServerContext map_context;
  EXPECT_EQ(service_.GetGlobalMap(&map_context, &map_request, &map).error_code(),
            StatusCode::NOT_FOUND);
}

TEST_F(HandlerTest, NewRevisionReplacesTheOldOne) {
  ASSERT_TRUE(Register("r1", true).ok());
  EXPECT_EQ(Upload("r1", testing::MakeSubmapUpload(0, 0)).acks(0).code(), 0);
  ASSERT_TRUE(WaitCovered());
  // Revision 1 moved the submap 10 m away: the old cells must disappear.
  EXPECT_EQ(Upload("r1", testing::MakeSubmapUpload(0, 1, Rigid2d(10, 0, 0))).acks(0).code(), 0);
  const auto snapshot = WaitCovered();
  ASSERT_TRUE(snapshot);
  EXPECT_NEAR(snapshot->grid.geometry.origin.x(), 10.0, 1e-6);
  EXPECT_EQ(snapshot->grid.geometry.width, 40);
}

}  // namespace
}  // namespace fleetmap
