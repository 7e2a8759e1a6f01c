#ifndef FLEETMAP_TESTS_SUPPORT_TEST_SUPPORT_H_
#define FLEETMAP_TESTS_SUPPORT_TEST_SUPPORT_H_

// Helpers shared by every test: pose matchers, synthetic worlds and scans, data-set lookup.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gmock/gmock.h>

#include "shared/core/laser_scan.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::testing {

// Matches a Rigid2d within a translation (metres) and rotation (radians) tolerance.
MATCHER_P3(IsNearPose, expected, translation_tolerance, rotation_tolerance,
           "is within tolerance of " + ::testing::PrintToString(expected)) {
  const double dt = (arg.translation() - expected.translation()).norm();
  const double dr = std::abs(NormalizeAngle(arg.rotation() - expected.rotation()));
  *result_listener << "translation error " << dt << ", rotation error " << dr;
  return dt <= translation_tolerance && dr <= rotation_tolerance;
}

// A world made of line segments, for generating exact synthetic scans.
struct Segment {
  Eigen::Vector2d a;
  Eigen::Vector2d b;
};
using SegmentWorld = std::vector<Segment>;

// The four walls of an axis-aligned box [min, max].
SegmentWorld BoxWorld(const Eigen::Vector2d& min, const Eigen::Vector2d& max);
// Appends the walls of a box to a world.
void AddBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max, SegmentWorld* world);
// Appends a 90-gon standing in for a cylinder (a robot's body, a post).
void AddCylinder(const Eigen::Vector2d& center, double radius, SegmentWorld* world);

// A noise-free scan of `world` from `robot_in_world`: beam i at angle_min + i * increment.
LaserScan SimulateScan(const SegmentWorld& world, const Rigid2d& robot_in_world, int beams = 181,
                       float angle_min = static_cast<float>(-M_PI / 2),
                       float angle_increment = static_cast<float>(M_PI / 180),
                       float range_max = 8.0f, const Rigid2d& sensor_in_robot = Rigid2d());

// The directory of the public data sets (FLEETMAP_DATA_DIR), when it exists.
std::optional<std::string> DataDir();
// Path of a data file below DataDir(), when it exists.
std::optional<std::string> DataFile(const std::string& relative);

// Build and source trees, from the environment CTest sets (fall back to the current directory).
std::string BinaryDir();
std::string SourceDir();
// The build tree this test binary belongs to, where tests find the product's programs:
// FLEETMAP_BINARY_DIR when set, else three levels above the running binary
// (<build>/tests/<folder>/<test>), else BinaryDir().
std::string TestBuildDir();
// Runs `program` (a path below TestBuildDir()) with `args` through the shell, its output and
// errors into `log`. The exit code, or -1 when it did not exit.
int RunProgram(const std::string& program, const std::string& args, const std::string& log);
// A file's whole text ("" when it cannot be read).
std::string ReadWholeFile(const std::string& path);

// A fresh empty directory under the system temp dir, named `prefix`-<random>, removed with
// everything in it when this goes out of scope. Tests used to leave their folders in /tmp by
// the hundred; this cleans up after passing tests, but keeps the folder (and prints its path to
// stderr) when the current test has failed, so the failing run's files can be inspected.
// Declare it before whatever writes into it (a server, a child process, an open database), so
// that those are destroyed first. Throws std::runtime_error (a test failure) when it cannot
// create the folder.
class ScopedTempDir {
 public:
  explicit ScopedTempDir(const std::string& prefix);
  ~ScopedTempDir();
  ScopedTempDir(const ScopedTempDir&) = delete;
  ScopedTempDir& operator=(const ScopedTempDir&) = delete;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace fleetmap::testing

// Skips the current test with a message when a public data file is absent.
#define FLEETMAP_REQUIRE_DATA(var, relative)                                 \
  const auto var##_opt = ::fleetmap::testing::DataFile(relative);            \
  if (!var##_opt) GTEST_SKIP() << "data set not present: " << (relative);    \
  const std::string var = *var##_opt

#endif  // FLEETMAP_TESTS_SUPPORT_TEST_SUPPORT_H_
