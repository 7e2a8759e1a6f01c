#include "robot_agent/sim/camera_model.h"

#include <algorithm>
#include <cmath>

namespace fleetmap::sim {
namespace {

constexpr int kNoiseTableBits = 16;
constexpr uint64_t kNoiseMask = (1u << kNoiseTableBits) - 1;
constexpr Rgb kWall{200, 196, 186};
constexpr Rgb kSkirting{90, 80, 70};
constexpr Rgb kFloor{120, 112, 104};
constexpr Rgb kCeiling{225, 225, 220};
constexpr Rgb kFog{150, 150, 150};
constexpr double kSkirtingHeight = 0.1;

Rgb Scale(const Rgb& color, double factor) {
  auto channel = [factor](uint8_t value) {
    return static_cast<uint8_t>(std::clamp(std::lround(value * factor), 0L, 255L));
  };
  return Rgb{channel(color.r), channel(color.g), channel(color.b)};
}

// Fills the pixels of column u whose centres lie in [top, bottom).
void FillRows(RgbImage* image, int u, double top, double bottom, const Rgb& color) {
  const int first = std::max(0, static_cast<int>(std::ceil(top - 0.5)));
  const int last = std::min(image->height, static_cast<int>(std::ceil(bottom - 0.5)));
  uint8_t* pixel = image->pixels.data() + (static_cast<size_t>(first) * image->width + u) * 3;
  const size_t stride = static_cast<size_t>(image->width) * 3;
  for (int v = first; v < last; ++v, pixel += stride) {
    pixel[0] = color.r;
    pixel[1] = color.g;
    pixel[2] = color.b;
  }
}

double DistanceShade(double distance) { return 1.0 / (1.0 + 0.015 * distance); }

}  // namespace

double LightingAt(const Eigen::Vector2d& point, double variation) {
  return 1.0 + variation * std::sin(0.9 * point.x() + 0.3) * std::sin(0.7 * point.y() + 1.1);
}

CameraModel::CameraModel(const CameraOptions& options, uint64_t noise_seed) : options_(options) {
  const double half_fov = 0.5 * options.hfov_deg * M_PI / 180.0;
  intrinsics_.fx = 0.5 * options.width / std::tan(half_fov);
  intrinsics_.fy = intrinsics_.fx;
  intrinsics_.cx = 0.5 * options.width;
  intrinsics_.cy = 0.5 * options.height;
  column_angle_.resize(static_cast<size_t>(options.width));
  for (int u = 0; u < options.width; ++u) {
    column_angle_[static_cast<size_t>(u)] = std::atan2(intrinsics_.cx - (u + 0.5), intrinsics_.fx);
  }
  // Per-pixel noise comes from a table read at random offsets: drawing 900k Gaussians per frame
  // would dominate the simulator's run time.
  Rng rng(noise_seed);
  noise_table_.resize(kNoiseMask + 1);
  for (int8_t& value : noise_table_) {
    value = static_cast<int8_t>(
        std::clamp(std::lround(rng.Gaussian(options.pixel_noise)), -127L, 127L));
  }
}

Rigid2d CameraModel::mount() const {
  return Rigid2d(options_.mount_x, options_.mount_y, options_.mount_yaw);
}

double CameraModel::ColumnOfBearing(double bearing) const {
  return intrinsics_.cx - intrinsics_.fx * std::tan(bearing);
}

double CameraModel::RowOfHeight(double z, double depth) const {
  return intrinsics_.cy - intrinsics_.fy * (z - options_.mount_z) / depth;
}

void CameraModel::Render(const World& world, const Rigid2d& robot_in_world,
                         const std::vector<Cylinder>& cylinders, double exposure, Rng* rng,
                         RgbImage* image) const {
  image->width = options_.width;
  image->height = options_.height;
  image->pixels.resize(static_cast<size_t>(options_.width) * options_.height * 3);
  const Rigid2d camera_in_world = robot_in_world * mount();
  // Floor and ceiling: one colour per row, darker with the distance the row looks at.
  const double light = exposure * LightingAt(camera_in_world.translation(),
                                             options_.lighting_variation);
  const size_t row_bytes = static_cast<size_t>(options_.width) * 3;
  for (int v = 0; v < options_.height; ++v) {
    const double below_horizon = v + 0.5 - intrinsics_.cy;
    Rgb color;
    if (below_horizon > 0) {
      const double distance = intrinsics_.fy * options_.mount_z / below_horizon;
      color = Scale(kFloor, light * DistanceShade(distance));
    } else {
      const double above = std::max(1e-3, -below_horizon);
      const double distance = intrinsics_.fy * (world.wall_height - options_.mount_z) / above;
      color = Scale(kCeiling, light * DistanceShade(distance));
    }
    uint8_t* row = image->pixels.data() + v * row_bytes;
    for (int u = 0; u < options_.width; ++u) {
      row[3 * u] = color.r;
      row[3 * u + 1] = color.g;
      row[3 * u + 2] = color.b;
    }
  }
  for (int u = 0; u < options_.width; ++u) {
    RenderColumn(world, camera_in_world, cylinders, exposure, u, image);
  }
  if (rng == nullptr || options_.pixel_noise <= 0.0) return;
  for (int v = 0; v < options_.height; ++v) {
    const uint64_t offset = rng->Next();
    uint8_t* row = image->pixels.data() + v * row_bytes;
    for (size_t i = 0; i < row_bytes; ++i) {
      const int value = row[i] + noise_table_[(offset + i) & kNoiseMask];
      row[i] = static_cast<uint8_t>(std::clamp(value, 0, 255));
    }
  }
}

void CameraModel::RenderColumn(const World& world, const Rigid2d& camera_in_world,
                               const std::vector<Cylinder>& cylinders, double exposure, int u,
                               RgbImage* image) const {
  const double offset = column_angle_[static_cast<size_t>(u)];
  const double cos_offset = std::cos(offset);
  const double angle = camera_in_world.rotation() + offset;
  const Eigen::Vector2d origin = camera_in_world.translation();
  const RayHit hit = world.CastRay(origin, angle, options_.max_depth);
  const double wall_depth = std::max(1e-3, hit.distance * cos_offset);
  const double top = RowOfHeight(world.wall_height, wall_depth);
  const double bottom = RowOfHeight(0.0, wall_depth);
  if (!hit.hit) {
    FillRows(image, u, top, bottom, Scale(kFog, exposure));
  } else {
    const double factor = exposure * (hit.x_face ? 0.85 : 1.0) * DistanceShade(hit.distance) *
                          LightingAt(hit.point, options_.lighting_variation);
    FillRows(image, u, top, bottom, Scale(kWall, factor));
    FillRows(image, u, RowOfHeight(kSkirtingHeight, wall_depth), bottom,
             Scale(kSkirting, factor));
    if (const WallPatch* patch = world.PatchAt(hit.point)) {
      FillRows(image, u, RowOfHeight(patch->z_max, wall_depth),
               RowOfHeight(patch->z_min, wall_depth), Scale(patch->color, factor));
    }
  }
  // Cylinders in front of the wall, far to near so nearer ones cover farther ones.
  const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
  std::pair<double, size_t> in_front[16];
  size_t count = 0;
  for (size_t i = 0; i < cylinders.size(); ++i) {
    const double t = RayCircleDistance(origin, direction, cylinders[i].center,
                                       cylinders[i].radius);
    if (t < hit.distance && count < 16) in_front[count++] = {t, i};
  }
  std::sort(in_front, in_front + count, [](const auto& a, const auto& b) { return a > b; });
  for (size_t k = 0; k < count; ++k) {
    const auto [t, i] = in_front[k];
    const Cylinder& cylinder = cylinders[i];
    const Eigen::Vector2d point = origin + t * direction;
    const Eigen::Vector2d normal = (point - cylinder.center) / cylinder.radius;
    const double facing = std::max(0.0, -normal.dot(direction));
    const double factor = exposure * (0.55 + 0.45 * facing) * DistanceShade(t) *
                          LightingAt(cylinder.center, options_.lighting_variation);
    const double depth = std::max(1e-3, t * cos_offset);
    FillRows(image, u, RowOfHeight(cylinder.z_max, depth), RowOfHeight(cylinder.z_min, depth),
             Scale(cylinder.color, factor));
  }
}

}  // namespace fleetmap::sim
