#include "robot_agent/detection/colour_model.h"

#include <fstream>

#include <gtest/gtest.h>

#include "robot_agent/detection/calibration.h"
#include "robot_agent/detection/colour_model_io.h"
#include "tests/support/test_support.h"

namespace fleetmap {
namespace {

TEST(ColourTest, HsvOfPrimaries) {
  EXPECT_NEAR(BgrToHsv(0, 0, 255).hue, 0.0, 1e-9);
  EXPECT_NEAR(BgrToHsv(0, 255, 0).hue, 120.0, 1e-9);
  EXPECT_NEAR(BgrToHsv(255, 0, 0).hue, 240.0, 1e-9);
  EXPECT_NEAR(BgrToHsv(255, 0, 0).saturation, 1.0, 1e-9);
  EXPECT_NEAR(BgrToHsv(128, 128, 128).saturation, 0.0, 1e-9);
  EXPECT_NEAR(BgrToHsv(0, 0, 0).value, 0.0, 1e-9);
}

ColourModel GreenAndRed() {
  ColourModel model;
  model.markers.push_back({"green", ColourHistogram::FromHueRange(120.0, 15.0, 0.5)});
  model.markers.push_back({"red", ColourHistogram::FromHueRange(0.0, 12.0, 0.5)});
  model.background = ColourHistogram::FromHueRange(30.0, 20.0, 0.0, 0.3);
  return model;
}

TEST(ColourTest, LookupTableClassifiesByHue) {
  const ColourLut lut(GreenAndRed());
  EXPECT_EQ(lut.Label(40, 200, 40), 1);   // green
  EXPECT_EQ(lut.Label(40, 40, 200), 2);   // red
  EXPECT_EQ(lut.Label(20, 20, 80), 2);    // dark red is still red
  EXPECT_EQ(lut.Label(200, 40, 40), 0);   // blue: nobody's
  EXPECT_EQ(lut.Label(150, 160, 170), 0); // grey wall
  EXPECT_EQ(lut.Label(3, 3, 3), 0);       // too dark for a hue
}

TEST(ColourTest, ModelSurvivesYamlRoundTrip) {
  const testing::ScopedTempDir temp("colour_model");
  const std::string& dir = temp.path();
  const std::string path = dir + "/model.yaml";
  std::string error;
  ASSERT_TRUE(WriteColourModel(path, GreenAndRed(), &error)) << error;
  ColourModel read;
  ASSERT_TRUE(ReadColourModel(path, &read, &error)) << error;
  ASSERT_EQ(read.markers.size(), 2u);
  EXPECT_EQ(read.markers[1].robot_id, "red");
  EXPECT_EQ(read.markers[1].histogram.counts(), GreenAndRed().markers[1].histogram.counts());
  EXPECT_DOUBLE_EQ(read.min_likelihood_ratio, GreenAndRed().min_likelihood_ratio);
}

TEST(ColourTest, BadModelFilesGiveMessages) {
  const testing::ScopedTempDir temp("colour_model_bad");
  const std::string& dir = temp.path();
  ColourModel model;
  std::string error;
  EXPECT_FALSE(ReadColourModel(dir + "/missing.yaml", &model, &error));
  EXPECT_NE(error.find("missing.yaml"), std::string::npos);
  const std::string path = dir + "/bad.yaml";
  std::ofstream(path) << "hue_bins: 32\nsaturation_bins: 16\nmarkers:\n  - robot_id: a\n"
                         "    counts: [1, 2, 3]\nbackground:\n  counts: []\n";
  EXPECT_FALSE(ReadColourModel(path, &model, &error));
  EXPECT_NE(error.find("counts"), std::string::npos);
  std::ofstream(path) << "[not, a, map";
  EXPECT_FALSE(ReadColourModel(path, &model, &error));
}

TEST(CalibrationTest, LearnsMarkerAndBackgroundFromBoxes) {
  BgrImage image(64, 48);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      uint8_t* p = image.pixel(x, y);
      const bool marker = x >= 20 && x < 30 && y >= 10 && y < 30;
      p[0] = marker ? 40 : 150;
      p[1] = marker ? 200 : 160;
      p[2] = marker ? 40 : 170;
    }
  }
  ColourCalibrator calibrator;
  std::string error;
  ASSERT_TRUE(calibrator.AddFrame(image.view(), {{"green", {20, 10, 10, 20}}}, &error)) << error;
  EXPECT_GT(calibrator.marker_pixels("green"), 50);
  const ColourLut lut(calibrator.Build());
  EXPECT_EQ(lut.Label(40, 200, 40), 1);
  EXPECT_EQ(lut.Label(150, 160, 170), 0);
  EXPECT_FALSE(calibrator.AddFrame(image.view(), {{"green", {60, 10, 10, 20}}}, &error));
  EXPECT_FALSE(calibrator.AddFrame(BgrImageView(), {}, &error));
}

TEST(CalibrationTest, HiddenMarkersStayOutOfBothHistograms) {
  BgrImage image(64, 48);
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      uint8_t* p = image.pixel(x, y);
      const bool marker = x >= 20 && x < 30 && y >= 10 && y < 30;
      p[0] = marker ? 40 : 150;
      p[1] = marker ? 200 : 160;
      p[2] = marker ? 40 : 170;
    }
  }
  ColourCalibrator calibrator;
  std::string error;
  LabelledMarker hidden{"green", {20, 10, 10, 20}, true};
  ASSERT_TRUE(calibrator.AddFrame(image.view(), {hidden}, &error)) << error;
  EXPECT_EQ(calibrator.marker_pixels("green"), 0);
  const ColourModel model = calibrator.Build();
  EXPECT_TRUE(model.markers.empty());
  // Nothing green reached the background either.
  const Hsv green = BgrToHsv(40, 200, 40);
  EXPECT_EQ(model.background.counts()[ColourHistogram::BinOf(green.hue, green.saturation)], 0.0);
}

TEST(CalibrationTest, ProjectsMarkerBox) {
  CameraModel camera;
  MarkerGeometry geometry;
  const ImageBox box = ProjectMarker(camera, geometry, 4.0, 0.0);
  EXPECT_NEAR(box.x + 0.5 * box.width, camera.cx + 0.5, 1.0);
  EXPECT_NEAR(box.width, 2.0 * camera.fx * geometry.marker_radius / 4.0, 2.0);
  EXPECT_EQ(ProjectMarker(camera, geometry, 4.0, 2.0).width, 0);  // behind the camera
}

}  // namespace
}  // namespace fleetmap
