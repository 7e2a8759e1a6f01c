#ifndef FLEETMAP_ROBOT_AGENT_SIM_CAMERA_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_SIM_CAMERA_MODEL_H_

#include <cstdint>
#include <vector>

#include "robot_agent/sim/laser_model.h"
#include "robot_agent/sim/rng.h"
#include "robot_agent/sim/scenario.h"
#include "robot_agent/sim/world.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

// 8-bit RGB pixels, rows top to bottom, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;
};

// Pinhole intrinsics in pixels; u grows right, v grows down; pixel (u, v) covers [u, u + 1).
struct CameraIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
};

// Renders a colour view of the world by casting one ray per image column (walls are vertical
// and floors flat, so a column is ceiling / wall / floor plus any cylinders in front), with
// lighting that varies over the floor plan and per frame, and additive pixel noise.
class CameraModel {
 public:
  CameraModel(const CameraOptions& options, uint64_t noise_seed);

  const CameraOptions& options() const { return options_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  // The camera's planar pose on the robot (x forward, y left, yaw).
  Rigid2d mount() const;

  // `exposure` scales all brightness (1 = nominal); `rng` draws the per-frame noise offsets (nullptr
  // for a noise-free image).
  void Render(const World& world, const Rigid2d& robot_in_world,
              const std::vector<Cylinder>& cylinders, double exposure, Rng* rng,
              RgbImage* image) const;

  // Image column (continuous, pixel edges at integers) of a bearing in the camera frame (radians,
  // positive to the left); meaningful for |bearing| < 90 degrees.
  double ColumnOfBearing(double bearing) const;
  // Image row (continuous) where a point at height z and forward depth `depth` appears.
  double RowOfHeight(double z, double depth) const;

 private:
  void RenderColumn(const World& world, const Rigid2d& camera_in_world,
                    const std::vector<Cylinder>& cylinders, double exposure, int u,
                    RgbImage* image) const;

  const CameraOptions options_;
  CameraIntrinsics intrinsics_;
  std::vector<int8_t> noise_table_;
  std::vector<double> column_angle_;  // per column, radians relative to the optical axis
  std::vector<Rgb> floor_row_;        // per row below the horizon (nominal exposure)
  std::vector<Rgb> ceiling_row_;      // per row above the horizon
};

// Brightness of the building's lighting at a floor position (ceiling lights every few metres).
double LightingAt(const Eigen::Vector2d& point, double variation);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_CAMERA_MODEL_H_
