// The handlers against the in-memory store, called directly (no network).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>

#include "map_server/server/density_relay.h"
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
  static MergeWorkerOptions WorkerOptions() {
    MergeWorkerOptions options;
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

// A robot localizing in a known map sends no submaps and is shown where its map is placed: the
// global frame itself, or its registered pose.
TEST_F(HandlerTest, ALocalizationOnlyRobotIsPlacedByItsMapAndSendsNoSubmaps) {
  for (const auto& [id, with_pose] : {std::pair{"in_global", false}, {"in_file", true}}) {
    grpc::ServerContext context;
    v1::RegisterRobotResponse response;
    auto request = testing::MakeRegistration(id, with_pose, Rigid2d(3.0, -1.0, 0.25));
    request.set_localization_only(true);
    ASSERT_TRUE(service_.RegisterRobot(&context, &request, &response).ok());
  }
  // A robot that has mapped cannot turn into a localizing one under the same id.
  ASSERT_TRUE(Register("mapper", false).ok());
  ASSERT_EQ(Upload("mapper", testing::MakeSubmapUpload(0, 0)).acks(0).code(), 0);
  {
    grpc::ServerContext context;
    v1::RegisterRobotResponse response;
    auto request = testing::MakeRegistration("mapper", false, Rigid2d());
    request.set_localization_only(true);
    const grpc::Status refused = service_.RegisterRobot(&context, &request, &response);
    EXPECT_EQ(refused.error_code(), StatusCode::FAILED_PRECONDITION);
    EXPECT_NE(refused.error_message().find("id of its own"), std::string::npos);
  }
  grpc::Status status;
  Upload("in_global", testing::MakeSubmapUpload(0, 0), &status);
  EXPECT_EQ(status.error_code(), StatusCode::FAILED_PRECONDITION);
  EXPECT_NE(status.error_message().find("localization only"), std::string::npos)
      << status.error_message();
  EXPECT_EQ(store_.CountSubmapIds("in_global"), 0);

  v1::GetRobotsResponse robots;
  for (int i = 0; i < 500; ++i) {  // the worker picks registrations up asynchronously
    grpc::ServerContext context;
    const v1::GetRobotsRequest request;
    robots.Clear();
    ASSERT_TRUE(service_.GetRobots(&context, &request, &robots).ok());
    if (robots.robots_size() == 3 && robots.robots(0).placement().placed() &&
        robots.robots(1).placement().placed()) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(robots.robots_size(), 3);
  const v1::RobotPlacement& in_file = robots.robots(0).placement();  // sorted by id
  const v1::RobotPlacement& in_global = robots.robots(1).placement();
  EXPECT_TRUE(in_global.placed());
  EXPECT_EQ(in_global.source(), "localization");
  EXPECT_DOUBLE_EQ(in_global.local_in_global().x(), 0.0);
  EXPECT_DOUBLE_EQ(in_global.local_in_global().theta(), 0.0);
  EXPECT_TRUE(in_file.placed());
  EXPECT_EQ(in_file.source(), "localization");
  EXPECT_DOUBLE_EQ(in_file.local_in_global().x(), 3.0);
  EXPECT_DOUBLE_EQ(in_file.local_in_global().theta(), 0.25);
}

// Collaborative localization: a density is checked, then relayed live to the seen robot's
// subscriptions only.
TEST_F(HandlerTest, PoseDensitiesAreCheckedAndRelayedToTheSeenRobot) {
  ASSERT_TRUE(Register("seer", false).ok());
  ASSERT_TRUE(Register("lost", false).ok());
  v1::PoseDensity density;
  density.set_observer_id("seer");
  density.set_observed_id("lost");
  density.set_timestamp(12.5);
  v1::PoseDensityKernel* kernel = density.add_kernels();
  kernel->set_weight(1.0);
  kernel->set_x(3.0);
  kernel->set_var_x(0.01);
  kernel->set_var_y(0.01);
  auto send = [&](const v1::PoseDensity& d, v1::SendPoseDensityResponse* response) {
    grpc::ServerContext context;
    return service_.SendPoseDensity(&context, &d, response);
  };
  v1::SendPoseDensityResponse response;
  ASSERT_TRUE(send(density, &response).ok());
  EXPECT_EQ(response.receivers(), 0) << "nobody listens yet: dropped";

  struct Bad {
    std::function<void(v1::PoseDensity*)> change;
    StatusCode code;
    std::string message;
  };
  const std::vector<Bad> bad = {
      {[](v1::PoseDensity* d) { d->set_observed_id("ghost"); }, StatusCode::NOT_FOUND, "ghost"},
      {[](v1::PoseDensity* d) { d->set_observed_id("seer"); }, StatusCode::INVALID_ARGUMENT,
       "same robot"},
      {[](v1::PoseDensity* d) { d->clear_kernels(); }, StatusCode::INVALID_ARGUMENT, "1-256"},
      {[](v1::PoseDensity* d) { d->mutable_kernels(0)->set_cov_xy(0.5); },
       StatusCode::INVALID_ARGUMENT, "positive definite"},
      {[](v1::PoseDensity* d) { d->mutable_kernels(0)->set_x(NAN); }, StatusCode::INVALID_ARGUMENT,
       "finite"},
      {[](v1::PoseDensity* d) { d->mutable_kernels(0)->set_weight(0.0); },
       StatusCode::INVALID_ARGUMENT, "weight"},
  };
  for (const Bad& b : bad) {
    v1::PoseDensity changed = density;
    b.change(&changed);
    const grpc::Status status = send(changed, &response);
    EXPECT_EQ(status.error_code(), b.code) << b.message;
    EXPECT_NE(status.error_message().find(b.message), std::string::npos) << status.error_message();
  }
}

TEST(DensityRelayTest, DeliversToTheSeenRobotOnlyAndDropsTheOldestWhenBehind) {
  DensityRelay relay(/*queue_limit=*/2);
  const auto lost = relay.Subscribe("lost");
  const auto other = relay.Subscribe("other");
  for (double t : {1.0, 2.0, 3.0}) {
    v1::PoseDensity density;
    density.set_observed_id("lost");
    density.set_timestamp(t);
    EXPECT_EQ(relay.Publish(density), 1);
  }
  EXPECT_EQ(lost->dropped(), 1);
  EXPECT_DOUBLE_EQ(lost->Pop(std::chrono::milliseconds(0))->timestamp(), 2.0);
  EXPECT_DOUBLE_EQ(lost->Pop(std::chrono::milliseconds(0))->timestamp(), 3.0);
  EXPECT_FALSE(lost->Pop(std::chrono::milliseconds(0)));
  EXPECT_FALSE(other->Pop(std::chrono::milliseconds(0)));
  relay.Unsubscribe("lost", lost);
  v1::PoseDensity late;
  late.set_observed_id("lost");
  EXPECT_EQ(relay.Publish(late), 0);
  // Closing wakes a waiting subscriber at once.
  relay.Close();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(other->Pop(std::chrono::seconds(10)));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
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
