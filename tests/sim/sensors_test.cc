#include <cmath>

#include <gtest/gtest.h>

#include "robot_agent/sim/camera_model.h"
#include "robot_agent/sim/visibility.h"
#include "robot_agent/sim/world_builder.h"

namespace fleetmap::sim {
namespace {

constexpr Rgb kMarker{40, 190, 40};

bool IsMarkerPixel(const RgbImage& image, int u, int v) {
  const uint8_t* p = image.pixels.data() + (static_cast<size_t>(v) * image.width + u) * 3;
  return p[1] > p[0] + 60 && p[1] > p[2] + 60;
}

// Columns holding marker pixels on row v: [first, last], or first > last when none.
std::pair<int, int> MarkerColumns(const RgbImage& image, int v) {
  int first = image.width, last = -1;
  for (int u = 0; u < image.width; ++u) {
    if (IsMarkerPixel(image, u, v)) {
      first = std::min(first, u);
      last = std::max(last, u);
    }
  }
  return {first, last};
}

std::vector<Cylinder> MarkerAt(const Eigen::Vector2d& center) {
  return {Cylinder{center, 0.2, 0.0, 0.35, Rgb{55, 55, 60}},
          Cylinder{center, 0.2, 0.35, 0.65, kMarker}};
}

World OpenRoom() {
  WorldBuilder builder("hall", 0.05, Eigen::Vector2d(20.0, 20.0));
  builder.Carve({0.2, 0.2}, {19.8, 19.8});
  return builder.Build();
}

TEST(CameraTest, MarkerAppearsAtTheRightColumnAndSize) {
  const World world = OpenRoom();
  CameraOptions options;
  options.pixel_noise = 0.0;
  options.lighting_variation = 0.0;
  const CameraModel camera(options, 1);
  const Rigid2d observer(3.0, 10.0, 0.1);
  const Eigen::Vector2d target(7.5, 11.2);
  RgbImage image;
  camera.Render(world, observer, MarkerAt(target), 1.0, nullptr, &image);
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);

  const Eigen::Vector2d in_camera = (observer * camera.mount()).inverse() * target;
  const double distance = in_camera.norm();
  const double bearing = std::atan2(in_camera.y(), in_camera.x());
  const double half_angle = std::asin(0.2 / distance);
  const double left = camera.ColumnOfBearing(bearing + half_angle);
  const double right = camera.ColumnOfBearing(bearing - half_angle);
  // Row through the marker's middle height at the near surface depth.
  const double depth = in_camera.x() - 0.2;
  const int v = static_cast<int>(camera.RowOfHeight(0.5, depth));
  const auto [first, last] = MarkerColumns(image, v);
  ASSERT_LE(first, last) << "no marker pixels on row " << v;
  EXPECT_NEAR(0.5 * (first + last + 1), 0.5 * (left + right), 1.0);
  EXPECT_NEAR(last + 1 - first, right - left, 2.0);
  // Vertical extent: from marker_z_max to marker_z_min at the near surface.
  int top = image.height, bottom = -1;
  const int u = (first + last) / 2;
  for (int row = 0; row < image.height; ++row) {
    if (IsMarkerPixel(image, u, row)) {
      top = std::min(top, row);
      bottom = std::max(bottom, row);
    }
  }
  EXPECT_NEAR(top, camera.RowOfHeight(0.65, depth), 1.5);
  EXPECT_NEAR(bottom + 1, camera.RowOfHeight(0.35, depth), 1.5);
}

TEST(CameraTest, WallOccludesRobotBehindIt) {
  WorldBuilder builder("split", 0.05, Eigen::Vector2d(20.0, 20.0));
  builder.Carve({0.2, 0.2}, {19.8, 19.8});
  builder.Fill({9.0, 5.0}, {9.2, 15.0});  // a wall between the robots
  const World world = builder.Build();
  CameraOptions options;
  options.pixel_noise = 0.0;
  const CameraModel camera(options, 1);
  const Rigid2d observer(5.0, 10.0, 0.0);
  const Rigid2d hidden(13.0, 10.0, 0.0);
  RgbImage image;
  camera.Render(world, observer, MarkerAt(hidden.translation()), 1.0, nullptr, &image);
  int marker_pixels = 0;
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) marker_pixels += IsMarkerPixel(image, u, v);
  }
  EXPECT_EQ(marker_pixels, 0);
  const auto records = ComputeVisibility(0.0, world, {observer, hidden}, camera, 0.2, 0.2);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_TRUE(records[0].in_camera_fov);
  EXPECT_TRUE(records[0].occluded);
  EXPECT_FALSE(records[0].visible);

  // Without the wall the same pose is visible and rendered.
  const World open = OpenRoom();
  camera.Render(open, observer, MarkerAt(hidden.translation()), 1.0, nullptr, &image);
  EXPECT_LE(MarkerColumns(image, static_cast<int>(camera.RowOfHeight(0.5, 7.7))).first, 330);
  const auto open_records = ComputeVisibility(0.0, open, {observer, hidden}, camera, 0.2, 0.2);
  EXPECT_TRUE(open_records[0].visible);
  EXPECT_NEAR(open_records[0].range, 8.0, 1e-9);
  EXPECT_FALSE(open_records[1].in_camera_fov);  // the other robot looks away
}

}  // namespace
}  // namespace fleetmap::sim
