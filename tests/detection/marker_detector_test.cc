#include "robot_agent/detection/marker_detector.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "robot_agent/detection/calibration.h"
#include "robot_agent/detection/robot_detector.h"
#include "robot_agent/detection/synthetic/synthetic_dataset.h"

namespace fleetmap {
namespace {

constexpr double kDegree = M_PI / 180.0;

class MarkerDetectorTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    colours_ = new ColourModel(synthetic::LearnColourModel(CameraModel(), MarkerGeometry(),
                                                           synthetic::SceneOptions(), 20, 777));
  }
  static void TearDownTestSuite() { delete colours_; }

  // A 12 m x 8 m room; the observer "robot1" at (1, 4) looks along +x.
  static synthetic::World Room(int robots) {
    synthetic::World world;
    synthetic::AddRoom({0.0, 0.0}, {12.0, 8.0}, &world);
    world.robots = synthetic::DefaultRobots(robots);
    world.robots[0].pose = Observer();
    return world;
  }
  static Rigid2d Observer() { return Rigid2d(1.0, 4.0, 0.0); }

  std::vector<MarkerCandidate> Detect(const synthetic::World& world, double light = 1.0) {
    std::string error;
    auto detector = MarkerDetector::Create(camera_, geometry_, *colours_, {}, &error);
    EXPECT_TRUE(detector) << error;
    synthetic::RenderOptions render;
    render.light_gain = light;
    const BgrImage image = synthetic::RenderImage(world, "robot1", Observer(), camera_, geometry_, render);
    std::vector<MarkerCandidate> candidates;
    EXPECT_TRUE(detector->Detect(image.view(), &candidates, &error)) << error;
    return candidates;
  }

  CameraModel camera_;
  MarkerGeometry geometry_;
  static ColourModel* colours_;
};
ColourModel* MarkerDetectorTest::colours_ = nullptr;

TEST_F(MarkerDetectorTest, FindsMarkerAtKnownColumnAndSize) {
  synthetic::World world = Room(2);
  const double range = 4.0, bearing = 10.0 * kDegree;
  world.robots[1].pose = Rigid2d(Observer() * Eigen::Vector2d(range * std::cos(bearing),
                                                              range * std::sin(bearing)), 0.3);
  const std::vector<MarkerCandidate> candidates = Detect(world);
  ASSERT_EQ(candidates.size(), 1u);
  const MarkerCandidate& c = candidates[0];
  EXPECT_EQ(c.robot_id, "robot2");
  EXPECT_NEAR(c.bearing_in_camera, bearing, 0.2 * kDegree);
  const ImageBox expected = ProjectMarker(camera_, geometry_, range, bearing);
  EXPECT_NEAR(c.box.x, expected.x, 1.5);
  EXPECT_NEAR(c.box.width, expected.width, 2.0);
  EXPECT_NEAR(c.box.y, expected.y, 1.5);
  EXPECT_NEAR(c.box.height, expected.height, 2.0);
  EXPECT_NEAR(c.range_from_size, range, 0.1 * range);
  EXPECT_FALSE(c.truncated);
  EXPECT_GT(c.confidence, 0.5);
}

TEST_F(MarkerDetectorTest, MarkerCutByImageEdgeKeepsItsBearing) {
  synthetic::World world = Room(2);
  // Centre just inside the left border: part of the marker falls outside the image.
  const double range = 3.0;
  const double bearing = camera_.HalfFieldOfView() - 0.3 * std::asin(geometry_.marker_radius / range);
  world.robots[1].pose = Rigid2d(Observer() * Eigen::Vector2d(range * std::cos(bearing),
                                                              range * std::sin(bearing)), 0.0);
  const std::vector<MarkerCandidate> candidates = Detect(world);
  ASSERT_EQ(candidates.size(), 1u);
  EXPECT_TRUE(candidates[0].truncated);
  EXPECT_EQ(candidates[0].box.x, 0);
  EXPECT_NEAR(candidates[0].bearing_in_camera, bearing, 0.5 * kDegree);
  EXPECT_NEAR(candidates[0].range_from_size, range, 0.1 * range);
}

TEST_F(MarkerDetectorTest, TwoMarkersInOneFrame) {
  synthetic::World world = Room(3);
  world.robots[1].pose = Rigid2d(4.0, 5.0, 0.0);
  world.robots[2].pose = Rigid2d(7.0, 3.0, 1.0);
  std::vector<MarkerCandidate> candidates = Detect(world);
  ASSERT_EQ(candidates.size(), 2u);
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& a, const auto& b) { return a.robot_id < b.robot_id; });
  EXPECT_EQ(candidates[0].robot_id, "robot2");
  EXPECT_EQ(candidates[1].robot_id, "robot3");
  EXPECT_NEAR(candidates[0].bearing_in_camera, std::atan2(1.0, 3.0), 0.3 * kDegree);
  EXPECT_NEAR(candidates[1].bearing_in_camera, std::atan2(-1.0, 6.0), 0.3 * kDegree);
}

TEST_F(MarkerDetectorTest, DarkAndBrightLighting) {
  for (double light : {0.45, 1.5}) {
    synthetic::World world = Room(2);
    world.robots[1].pose = Rigid2d(5.0, 3.5, 0.0);
    const std::vector<MarkerCandidate> candidates = Detect(world, light);
    ASSERT_EQ(candidates.size(), 1u) << "light " << light;
    EXPECT_EQ(candidates[0].robot_id, "robot2");
    EXPECT_NEAR(candidates[0].bearing_in_camera, std::atan2(-0.5, 4.0), 0.3 * kDegree);
  }
}

TEST_F(MarkerDetectorTest, UnknownHueIsNotAMarker) {
  synthetic::World world = Room(2);
  world.robots[1].pose = Rigid2d(5.0, 4.0, 0.0);
  world.robots[1].marker_colour = {200, 40, 200};  // magenta: nobody's marker
  EXPECT_TRUE(Detect(world).empty());
}

TEST_F(MarkerDetectorTest, PosterPassesTheImageButNotTheLaser) {
  synthetic::World world = Room(2);
  world.robots[1].pose = Rigid2d(10.5, 1.0, 0.0);  // out of view
  // A wall 5 m ahead with a green patch of marker size at marker height on it.
  world.walls.push_back({{6.0, 2.0}, {6.0, 6.0}});
  synthetic::Poster poster;
  poster.a = {5.98, 3.8};
  poster.b = {5.98, 4.2};
  poster.colour = world.robots[1].marker_colour;
  world.posters.push_back(poster);
  const std::vector<MarkerCandidate> candidates = Detect(world);
  ASSERT_FALSE(candidates.empty());
  EXPECT_EQ(candidates[0].robot_id, "robot2");

  std::string error;
  auto detector = RobotDetector::Create(camera_, geometry_, *colours_, {}, &error);
  ASSERT_TRUE(detector) << error;
  const BgrImage image = synthetic::RenderImage(world, "robot1", Observer(), camera_, geometry_, {});
  const LaserScan scan = synthetic::RenderScan(world, "robot1", Observer(), geometry_, {});
  FrameDetections result;
  ASSERT_TRUE(detector->Detect(image.view(), scan, "robot1", &result, &error)) << error;
  EXPECT_TRUE(result.detections.empty());
  ASSERT_EQ(result.statuses.size(), result.candidates.size());
  EXPECT_EQ(result.statuses[0], FusionStatus::kSurfaceTooWide);
}

TEST_F(MarkerDetectorTest, WholePipelineMeasuresPosition) {
  synthetic::World world = Room(2);
  world.robots[1].pose = Rigid2d(6.0, 5.0, 0.0);
  std::string error;
  auto detector = RobotDetector::Create(camera_, geometry_, *colours_, {}, &error);
  ASSERT_TRUE(detector) << error;
  const BgrImage image = synthetic::RenderImage(world, "robot1", Observer(), camera_, geometry_, {});
  synthetic::LaserOptions laser;
  laser.seed = 3;
  const LaserScan scan = synthetic::RenderScan(world, "robot1", Observer(), geometry_, laser, 12.5);
  FrameDetections result;
  ASSERT_TRUE(detector->Detect(image.view(), scan, "robot1", &result, &error)) << error;
  ASSERT_EQ(result.detections.size(), 1u);
  const RobotDetection& d = result.detections[0];
  EXPECT_EQ(d.observer_id, "robot1");
  EXPECT_EQ(d.observed_id, "robot2");
  EXPECT_DOUBLE_EQ(d.timestamp, 12.5);
  EXPECT_LT((d.position_in_observer - Eigen::Vector2d(5.0, 1.0)).norm(), 0.03);
  EXPECT_GT(d.laser_returns, 3);
}

TEST_F(MarkerDetectorTest, BadImagesGiveErrorsNotCrashes) {
  std::string error;
  auto detector = MarkerDetector::Create(camera_, geometry_, *colours_, {}, &error);
  ASSERT_TRUE(detector) << error;
  std::vector<MarkerCandidate> candidates;
  EXPECT_FALSE(detector->Detect(BgrImageView(), &candidates, &error));
  EXPECT_NE(error.find("empty"), std::string::npos);
  const BgrImage small(320, 240);
  EXPECT_FALSE(detector->Detect(small.view(), &candidates, &error));
  EXPECT_NE(error.find("320x240"), std::string::npos);
  BgrImage grey(640, 480);
  BgrImageView one_channel = grey.view();
  one_channel.channels = 1;
  EXPECT_FALSE(detector->Detect(one_channel, &candidates, &error));
  EXPECT_TRUE(candidates.empty());
}

TEST_F(MarkerDetectorTest, InvalidSetupIsRefused) {
  std::string error;
  CameraModel camera;
  camera.fx = -1.0;
  EXPECT_FALSE(MarkerDetector::Create(camera, geometry_, *colours_, {}, &error));
  EXPECT_FALSE(error.empty());
  ColourModel duplicate = *colours_;
  duplicate.markers.push_back(duplicate.markers[0]);
  EXPECT_FALSE(MarkerDetector::Create(camera_, geometry_, duplicate, {}, &error));
  // A model without markers is valid and finds nothing.
  auto empty = MarkerDetector::Create(camera_, geometry_, ColourModel(), {}, &error);
  ASSERT_TRUE(empty) << error;
  std::vector<MarkerCandidate> candidates;
  EXPECT_TRUE(empty->Detect(BgrImage(640, 480).view(), &candidates, &error));
  EXPECT_TRUE(candidates.empty());
}

}  // namespace
}  // namespace fleetmap
