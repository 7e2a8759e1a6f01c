#include "robot_agent/detection/synthetic/synthetic_world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace fleetmap::synthetic {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double RaySegment(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                  const Eigen::Vector2d& a, const Eigen::Vector2d& b, double* along) {
  const Eigen::Vector2d e = b - a;
  const double denom = dir.x() * e.y() - dir.y() * e.x();
  if (std::abs(denom) < 1e-12) return kInf;
  const Eigen::Vector2d w = a - origin;
  const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
  const double u = (w.x() * dir.y() - w.y() * dir.x()) / denom;
  if (t <= 1e-9 || u < 0.0 || u > 1.0) return kInf;
  if (along) *along = u * e.norm();
  return t;
}

// First intersection of the ray with a circle; `facing` is |cos| between ray and normal.
double RayCircle(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                 const Eigen::Vector2d& center, double radius, double* facing) {
  const Eigen::Vector2d oc = origin - center;
  const double b = oc.dot(dir);
  const double c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0.0) return kInf;
  const double t = -b - std::sqrt(disc);
  if (t <= 1e-9) return kInf;
  if (facing) *facing = std::abs((oc + t * dir).normalized().dot(dir));
  return t;
}

struct Hit {
  double t;
  double low, high;  // heights it covers
  Bgr colour;
  double shade;
};

// Cheap Gaussian noise: a fixed table of normal samples indexed by xorshift.
class NoiseSource {
 public:
  explicit NoiseSource(uint32_t seed) : state_(seed * 2654435761u + 1u) {
    std::mt19937 engine(seed);
    std::normal_distribution<double> normal;
    for (double& v : table_) v = normal(engine);
  }
  double Next() {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    return table_[state_ & 4095u];
  }

 private:
  uint32_t state_;
  double table_[4096];
};

uint8_t ToByte(double v) { return static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }

}  // namespace

std::vector<Robot> DefaultRobots(int count) {
  static const Bgr kColours[] = {{40, 185, 45}, {45, 40, 200}, {205, 90, 35}, {30, 200, 215}};
  std::vector<Robot> robots;
  for (int i = 0; i < std::clamp(count, 0, 4); ++i) {
    robots.push_back({"robot" + std::to_string(i + 1), Rigid2d(), kColours[i]});
  }
  return robots;
}

void AddRoom(const Eigen::Vector2d& min, const Eigen::Vector2d& max, World* world) {
  const Eigen::Vector2d a = min, b(max.x(), min.y()), c = max, d(min.x(), max.y());
  world->walls.push_back({a, b});
  world->walls.push_back({b, c});
  world->walls.push_back({c, d});
  world->walls.push_back({d, a});
}

BgrImage RenderImage(const World& world, const std::string& observer_id,
                     const Rigid2d& observer_in_world, const CameraModel& camera,
                     const MarkerGeometry& geometry, const RenderOptions& options) {
  BgrImage image(camera.width, camera.height);
  NoiseSource noise(options.seed);
  const Rigid2d camera_in_world = observer_in_world * camera.camera_in_robot;
  const Eigen::Vector2d origin = camera_in_world.translation();
  std::vector<Hit> hits;
  for (int u = 0; u < camera.width; ++u) {
    const double bearing = camera.BearingOfColumn(u);
    const double angle = camera_in_world.rotation() + bearing;
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    const double cos_bearing = std::cos(bearing);
    hits.clear();
    for (const Wall& wall : world.walls) {
      double along = 0.0;
      const double t = RaySegment(origin, dir, wall.a, wall.b, &along);
      if (t == kInf) continue;
      const Eigen::Vector2d e = (wall.b - wall.a).normalized();
      const double facing = std::abs(e.x() * dir.y() - e.y() * dir.x());
      // Faint texture along the wall so the background is not one flat colour.
      const double texture = 0.93 + 0.07 * std::sin(along * 5.0) * std::sin(along * 1.3);
      hits.push_back({t, 0.0, world.wall_height, wall.colour, (0.7 + 0.3 * facing) * texture});
    }
    for (const Poster& poster : world.posters) {
      const double t = RaySegment(origin, dir, poster.a, poster.b, nullptr);
      if (t != kInf) hits.push_back({t - 1e-3, poster.bottom, poster.top, poster.colour, 0.95});
    }
    for (const Robot& robot : world.robots) {
      if (robot.id == observer_id) continue;
      double facing = 0.0;
      double t = RayCircle(origin, dir, robot.pose.translation(), geometry.body_radius, &facing);
      if (t != kInf) {
        hits.push_back({t, 0.0, geometry.marker_bottom, world.body, 0.6 + 0.4 * facing});
      }
      t = RayCircle(origin, dir, robot.pose.translation(), geometry.marker_radius, &facing);
      if (t != kInf) {
        hits.push_back({t, geometry.marker_bottom, geometry.marker_top, robot.marker_colour,
                        0.55 + 0.45 * facing});
      }
    }
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.t < b.t; });
    for (int v = 0; v < camera.height; ++v) {
      const double slope = (camera.cy - v) / camera.fy;
      Bgr colour = slope < 0.0 ? world.floor : world.ceiling;
      double shade = 1.0;
      for (const Hit& hit : hits) {
        const double z = camera.mount_height + slope * hit.t * cos_bearing;
        if (z >= hit.low && z <= hit.high) {
          colour = hit.colour;
          shade = hit.shade;
          break;
        }
      }
      const double gain = options.light_gain * shade;
      uint8_t* p = image.pixel(u, v);
      p[0] = ToByte(colour.b * gain + options.noise_sigma * noise.Next());
      p[1] = ToByte(colour.g * gain + options.noise_sigma * noise.Next());
      p[2] = ToByte(colour.r * gain + options.noise_sigma * noise.Next());
    }
  }
  return image;
}

LaserScan RenderScan(const World& world, const std::string& observer_id,
                     const Rigid2d& observer_in_world, const MarkerGeometry& geometry,
                     const LaserOptions& options, double timestamp) {
  std::mt19937 engine(options.seed);
  std::normal_distribution<double> normal(0.0, options.noise_sigma);
  const Rigid2d sensor_in_world = observer_in_world * options.sensor_in_robot;
  std::vector<float> ranges;
  for (int i = 0; i < options.beams; ++i) {
    const double angle =
        sensor_in_world.rotation() + options.angle_min + i * static_cast<double>(options.angle_increment);
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
    double best = kInf;
    for (const Wall& wall : world.walls) {
      best = std::min(best, RaySegment(sensor_in_world.translation(), dir, wall.a, wall.b, nullptr));
    }
    for (const Robot& robot : world.robots) {
      if (robot.id == observer_id) continue;
      best = std::min(best, RayCircle(sensor_in_world.translation(), dir, robot.pose.translation(),
                                      geometry.body_radius, nullptr));
    }
    if (best != kInf && options.noise_sigma > 0.0) best += normal(engine);
    ranges.push_back(static_cast<float>(best));
  }
  return MakeLaserScan(timestamp, options.angle_min, options.angle_increment, 0.0f,
                       options.range_max, ranges, options.sensor_in_robot);
}

std::vector<Sighting> TrueSightings(const World& world, const std::string& observer_id,
                                    const Rigid2d& observer_in_world, const CameraModel& camera,
                                    const MarkerGeometry& geometry) {
  std::vector<Sighting> sightings;
  const Rigid2d camera_in_world = observer_in_world * camera.camera_in_robot;
  const Rigid2d world_to_camera = camera_in_world.inverse();
  const Eigen::Vector2d origin = camera_in_world.translation();
  for (const Robot& robot : world.robots) {
    if (robot.id == observer_id) continue;
    Sighting s;
    s.robot_id = robot.id;
    s.position_in_observer = observer_in_world.inverse() * robot.pose.translation();
    const Eigen::Vector2d in_camera = world_to_camera * robot.pose.translation();
    s.camera_range = in_camera.norm();
    s.camera_bearing = std::atan2(in_camera.y(), in_camera.x());
    const double half = std::asin(std::min(1.0, geometry.marker_radius / s.camera_range));
    const double fov = camera.HalfFieldOfView();
    const double near_depth = in_camera.x() - geometry.marker_radius;
    const bool vertical_fit =
        near_depth > 0.0 && camera.RowOfHeight(geometry.marker_top, near_depth) >= -0.5 &&
        camera.RowOfHeight(geometry.marker_bottom, near_depth) <= camera.height - 0.5;
    s.fully_in_view = in_camera.x() > 0.0 && std::abs(s.camera_bearing) + half < fov && vertical_fit;
    s.partly_in_view = in_camera.x() > 0.0 && std::abs(s.camera_bearing) - half < fov;
    // Sight lines to the axis and both silhouette edges.
    const Eigen::Vector2d to_robot = robot.pose.translation() - origin;
    const Eigen::Vector2d side = Eigen::Vector2d(-to_robot.y(), to_robot.x()).normalized();
    for (double offset : {0.0, -0.9, 0.9}) {
      const Eigen::Vector2d target = robot.pose.translation() + offset * geometry.marker_radius * side;
      const double distance = (target - origin).norm() - geometry.marker_radius * 0.5;
      const Eigen::Vector2d dir = (target - origin).normalized();
      for (const Wall& wall : world.walls) {
        if (RaySegment(origin, dir, wall.a, wall.b, nullptr) < distance) s.occluded = true;
      }
      for (const Robot& other : world.robots) {
        if (other.id == observer_id || other.id == robot.id) continue;
        if (RayCircle(origin, dir, other.pose.translation(), geometry.body_radius, nullptr) <
            distance) {
          s.occluded = true;
        }
      }
    }
    sightings.push_back(s);
  }
  return sightings;
}

}  // namespace fleetmap::synthetic
