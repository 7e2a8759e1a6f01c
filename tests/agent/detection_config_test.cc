// The detection: section of robot.yaml, and the detection stage's handling of bad frames.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "robot_agent/agent/agent_config.h"
#include "robot_agent/agent/detection_factory.h"
#include "robot_agent/agent/detection_stage.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

using ::testing::HasSubstr;

class DetectionConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_.path() + "/robot.log") << "# empty log\n";
    std::ofstream(dir_.path() + "/frames.txt") << "# no frames\n";
  }
  // A log source with camera frames, plus `detection` (indented YAML lines).
  bool ParseLog(const std::string& detection, AgentConfig* config, std::string* error,
                const std::string& camera = "camera_frames: frames.txt") const {
    const std::string text =
        "robot: {id: r1}\noutbox: {path: o.db}\nsource:\n  carmen: {log: "
        "robot.log, " +
        camera + "}\ndetection:\n" + detection;
    return ParseAgentConfig(text, "robot.yaml", dir_.path(), config, error);
  }
  bool ParseSim(const std::string& detection, bool camera, AgentConfig* config,
                std::string* error) const {
    const std::string text =
        "robot: {id: robot1}\noutbox: {path: o.db}\nsource:\n  simulator: {scenario: "
        "department_3robots, robot: robot1, camera: " +
        std::string(camera ? "true" : "false") + "}\ndetection:\n" + detection;
    return ParseAgentConfig(text, "robot.yaml", dir_.path(), config, error);
  }
  const testing::ScopedTempDir dir_{"detection_config"};
};

TEST_F(DetectionConfigTest, ReadsEveryField) {
  AgentConfig config;
  std::string error;
  ASSERT_TRUE(ParseLog(R"(  enabled: true
  marker_hues: {r1: 120, r2: 220.5}
  hue_half_width: 10
  min_saturation: 0.4
  camera: {width: 320, height: 240, fx: 277, fy: 277, cx: 159.5, cy: 119.5,
           mount: {x: 0.1, y: 0.02, theta: 0.05}, mount_height: 0.5}
  marker: {radius: 0.15, bottom: 0.3, top: 0.6, body_radius: 0.18}
  laser_range_noise: 0.02
  max_time_difference: 0.04
  robot_ids: {r2: robot-two}
  mask_seen_robots: false
  mask_laser_bodies: true
)",
                       &config, &error))
      << error;
  const DetectionConfig& d = config.detection;
  EXPECT_TRUE(d.enabled);
  EXPECT_EQ(d.marker_hues.size(), 2u);
  EXPECT_DOUBLE_EQ(d.marker_hues.at("r2"), 220.5);
  EXPECT_DOUBLE_EQ(d.hue_half_width, 10.0);
  EXPECT_EQ(d.camera.width, 320);
  EXPECT_DOUBLE_EQ(d.camera.camera_in_robot.translation().y(), 0.02);
  EXPECT_DOUBLE_EQ(d.camera.camera_in_robot.rotation(), 0.05);
  EXPECT_DOUBLE_EQ(d.camera.mount_height, 0.5);
  EXPECT_DOUBLE_EQ(d.marker.body_radius, 0.18);
  EXPECT_DOUBLE_EQ(d.laser_range_noise, 0.02);
  EXPECT_DOUBLE_EQ(d.max_time_difference, 0.04);
  EXPECT_EQ(d.robot_ids.at("r2"), "robot-two");
  EXPECT_FALSE(d.mask_seen_robots);
  EXPECT_TRUE(d.mask_laser_bodies);
  EXPECT_FALSE(AgentConfig().detection.mask_laser_bodies);  // off unless asked for
}

TEST_F(DetectionConfigTest, SimulatorNeedsNothingButTheCamera) {
  AgentConfig config;
  std::string error;
  EXPECT_TRUE(ParseSim("  enabled: true\n", true, &config, &error)) << error;
  EXPECT_FALSE(ParseSim("  enabled: true\n", false, &config, &error));
  EXPECT_THAT(error, HasSubstr("source.simulator.camera: true"));
  // Disabled, the section is not checked further.
  EXPECT_TRUE(ParseSim("  enabled: false\n", false, &config, &error)) << error;
}

TEST_F(DetectionConfigTest, RefusesBadSettingsNamingTheField) {
  AgentConfig config;
  std::string error;
  EXPECT_FALSE(ParseLog("  enabled: true\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("a log needs marker colours"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: 120}\n", &config, &error, "x: 1"));
  EXPECT_THAT(error, HasSubstr("source.carmen.x"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: 120}\n", &config, &error,
                        "camera_frames: \"\""));
  EXPECT_THAT(error, HasSubstr("source.carmen.camera_frames"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  colour_model: none.yaml\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.colour_model: no such file"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  colour_model: robot.log\n  marker_hues: {r2: 1}\n",
                        &config, &error));
  EXPECT_THAT(error, HasSubstr("not both"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: 400}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.marker_hues.r2: must be in [0, 360)"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: green}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.marker_hues.r2"));
  EXPECT_FALSE(
      ParseLog("  enabled: true\n  marker_hues: {r2: 1}\n  camera: {fx: -3}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.camera:"));
  EXPECT_FALSE(
      ParseLog("  enabled: true\n  marker_hues: {r2: 1}\n  marker: {top: 0.1}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.marker:"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: 1}\n  max_time_difference: 0\n",
                        &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.max_time_difference: must be > 0"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hues: {r2: 1}\n  robot_ids: {r2: \"a b\"}\n",
                        &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.robot_ids.r2"));
  EXPECT_FALSE(ParseLog("  enabled: true\n  marker_hue: {r2: 1}\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.marker_hue: unknown field"));
  EXPECT_FALSE(ParseLog("  enabled: yes please\n", &config, &error));
  EXPECT_THAT(error, HasSubstr("detection.enabled: must be a boolean"));
}

// A stage over the default camera with a hue-only colour model.
std::unique_ptr<DetectionStage> HueStage(std::string* error) {
  DetectionSetup setup;
  setup.colours = ColourModelFromHues({{"r2", 120.0}}, 15.0, 0.35);
  DetectionStageOptions options;
  options.observer_id = "r1";
  return DetectionStage::Create(setup, options, error);
}

SensorEvent ScanAt(double t) {
  SensorEvent event;
  event.timestamp = t;
  LaserRecord laser;
  laser.scan = MakeLaserScan(t, -1.5f, 0.01f, 0.02f, 8.0f, std::vector<float>(301, 3.0f));
  event.laser = laser;
  return event;
}

SensorEvent FrameAt(double t, int width, int height, size_t bytes) {
  SensorEvent event;
  event.timestamp = t;
  CameraImage image;
  image.timestamp = t;
  image.width = width;
  image.height = height;
  image.bgr.assign(bytes, 90);
  event.camera = image;
  return event;
}

TEST(DetectionStageTest, PairsFramesWithScansAndCountsBadFrames) {
  std::string error;
  auto stage = HueStage(&error);
  ASSERT_NE(stage, nullptr) << error;
  std::vector<RobotDetection> detections;
  stage->Process(FrameAt(1.0, 640, 480, 640 * 480 * 3), &detections);  // waits for a scan
  stage->Process(ScanAt(1.01), &detections);                           // paired: plain grey
  stage->Process(FrameAt(1.58, 640, 480, 10), &detections);            // buffer too small
  stage->Process(ScanAt(1.6), &detections);
  stage->Process(FrameAt(1.7, 320, 240, 320 * 240 * 3), &detections);  // wrong size
  stage->Process(ScanAt(1.71), &detections);
  stage->Process(FrameAt(3.0, 640, 480, 640 * 480 * 3), &detections);  // no scan near it
  stage->Finish(&detections);
  EXPECT_TRUE(detections.empty());
  EXPECT_EQ(stage->counters().frames, 4);
  EXPECT_EQ(stage->counters().unusable_frames, 2);
  EXPECT_EQ(stage->counters().unpaired_frames, 1);
  EXPECT_EQ(stage->counters().detections, 0);
  EXPECT_THAT(stage->last_problem(), HasSubstr("camera frame at 1.7"));
}

TEST(DetectionStageTest, AMissingImageFileIsCountedNotFatal) {
  std::string error;
  auto stage = HueStage(&error);
  ASSERT_NE(stage, nullptr) << error;
  std::vector<RobotDetection> detections;
  SensorEvent frame;
  frame.timestamp = 2.0;
  CameraImage image;
  image.timestamp = 2.0;
  image.path = "/nonexistent/frame.png";
  frame.camera = image;
  stage->Process(ScanAt(2.0), &detections);
  stage->Process(frame, &detections);
  EXPECT_EQ(stage->counters().unusable_frames, 1);
  EXPECT_THAT(stage->last_problem(), HasSubstr("frame.png"));
}

}  // namespace
}  // namespace fleetmap
