#include "tests/support/test_support.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <system_error>

namespace fleetmap::testing {
namespace {

std::string NewTempDir(const std::string& prefix) {
  std::random_device rd;
  std::error_code error;
  const std::filesystem::path root = std::filesystem::temp_directory_path(error);
  if (!error) {
    for (int attempt = 0; attempt < 100; ++attempt) {
      const auto path = root / (prefix + "-" + std::to_string(rd()) + std::to_string(attempt));
      if (std::filesystem::create_directory(path, error)) return path.string();
      if (error) break;
    }
  }
  // Never fall back to the temp root itself: callers delete what they get.
  throw std::runtime_error("cannot create a temp directory " + prefix + "-* under " +
                           (root.empty() ? "$TMPDIR" : root.string()) + ": " +
                           (error ? error.message() : "no unused name"));
}

}  // namespace

SegmentWorld BoxWorld(const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
  SegmentWorld world;
  AddBox(min, max, &world);
  return world;
}

void AddBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max, SegmentWorld* world) {
  const Eigen::Vector2d a = min, b(max.x(), min.y()), c = max, d(min.x(), max.y());
  world->push_back({a, b});
  world->push_back({b, c});
  world->push_back({c, d});
  world->push_back({d, a});
}

void AddCylinder(const Eigen::Vector2d& center, double radius, SegmentWorld* world) {
  constexpr int kSides = 90;
  for (int i = 0; i < kSides; ++i) {
    const double a0 = 2.0 * M_PI * i / kSides, a1 = 2.0 * M_PI * (i + 1) / kSides;
    world->push_back({center + radius * Eigen::Vector2d(std::cos(a0), std::sin(a0)),
                      center + radius * Eigen::Vector2d(std::cos(a1), std::sin(a1))});
  }
}

namespace {

// Distance along the ray origin + t * direction to the segment, or +inf.
double RaySegment(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                  const Segment& s) {
  const Eigen::Vector2d e = s.b - s.a;
  const double denom = direction.x() * e.y() - direction.y() * e.x();
  if (std::abs(denom) < 1e-12) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d w = s.a - origin;
  const double t = (w.x() * e.y() - w.y() * e.x()) / denom;
  const double u = (w.x() * direction.y() - w.y() * direction.x()) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  return t;
}

}  // namespace

LaserScan SimulateScan(const SegmentWorld& world, const Rigid2d& robot_in_world, int beams,
                       float angle_min, float angle_increment, float range_max,
                       const Rigid2d& sensor_in_robot) {
  const Rigid2d sensor_in_world = robot_in_world * sensor_in_robot;
  std::vector<float> ranges;
  ranges.reserve(static_cast<size_t>(beams));
  for (int i = 0; i < beams; ++i) {
    const double a = sensor_in_world.rotation() + angle_min + i * static_cast<double>(angle_increment);
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& s : world) best = std::min(best, RaySegment(sensor_in_world.translation(), dir, s));
    ranges.push_back(static_cast<float>(best));
  }
  return MakeLaserScan(0.0, angle_min, angle_increment, 0.0f, range_max, ranges, sensor_in_robot);
}

std::optional<std::string> DataDir() {
  const char* env = std::getenv("FLEETMAP_DATA_DIR");
  const std::string dir = env ? env : FLEETMAP_DEFAULT_DATA_DIR;
  if (std::filesystem::is_directory(dir)) return dir;
  return std::nullopt;
}

std::optional<std::string> DataFile(const std::string& relative) {
  const auto dir = DataDir();
  if (!dir) return std::nullopt;
  const std::string path = *dir + "/" + relative;
  if (std::filesystem::exists(path)) return path;
  return std::nullopt;
}

std::string BinaryDir() {
  const char* env = std::getenv("FLEETMAP_BINARY_DIR");
  return env ? env : FLEETMAP_DEFAULT_BINARY_DIR;
}

std::string SourceDir() {
  const char* env = std::getenv("FLEETMAP_SOURCE_DIR");
  return env ? env : FLEETMAP_DEFAULT_SOURCE_DIR;
}

std::string TestBuildDir() {
  if (std::getenv("FLEETMAP_BINARY_DIR")) return BinaryDir();
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return BinaryDir();
  return self.parent_path().parent_path().parent_path().string();
}

int RunProgram(const std::string& program, const std::string& args, const std::string& log) {
  const std::string command = TestBuildDir() + "/" + program + " " + args + " > " + log + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

ScopedTempDir::ScopedTempDir(const std::string& prefix) : path_(NewTempDir(prefix)) {}

ScopedTempDir::~ScopedTempDir() {
  if (::testing::Test::HasFailure()) {
    std::cerr << "test failed: keeping " << path_ << "\n";
    return;
  }
  std::error_code error;
  std::filesystem::remove_all(path_, error);
  if (error) std::cerr << "cannot remove " << path_ << ": " << error.message() << "\n";
}

}  // namespace fleetmap::testing
