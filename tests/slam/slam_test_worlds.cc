#include "tests/slam/slam_test_worlds.h"

#include <cmath>
#include <random>

namespace fleetmap::testing {

SegmentWorld CorridorRing() {
  SegmentWorld world = BoxWorld(Eigen::Vector2d(-10.0, -7.5), Eigen::Vector2d(10.0, 7.5));
  AddBox(Eigen::Vector2d(-8.0, -5.5), Eigen::Vector2d(8.0, 5.5), &world);
  for (double x = -8.0; x <= 8.0; x += 2.7) {
    AddBox(Eigen::Vector2d(x, -7.5), Eigen::Vector2d(x + 0.3, -7.2), &world);
    AddBox(Eigen::Vector2d(x + 1.1, 7.2), Eigen::Vector2d(x + 1.4, 7.5), &world);
  }
  for (double y = -5.0; y <= 5.0; y += 2.3) {
    AddBox(Eigen::Vector2d(-10.0, y), Eigen::Vector2d(-9.7, y + 0.3), &world);
    AddBox(Eigen::Vector2d(9.7, y + 0.8), Eigen::Vector2d(10.0, y + 1.1), &world);
  }
  return world;
}

std::vector<Rigid2d> PathPoses(const std::vector<Eigen::Vector2d>& corners, bool turn_after_last) {
  std::vector<Rigid2d> poses;
  double heading = 0.0;
  for (size_t c = 0; c + 1 < corners.size(); ++c) {
    const Eigen::Vector2d a = corners[c], b = corners[c + 1];
    const int steps = static_cast<int>((b - a).norm() / 0.1);
    for (int i = 0; i < steps; ++i) poses.emplace_back(a + (b - a) * (static_cast<double>(i) / steps), heading);
    if (turn_after_last || c + 2 < corners.size()) {
      for (int i = 1; i <= 10; ++i) poses.emplace_back(b, heading + i * 9.0 * (M_PI / 180.0));
    }
    heading += M_PI / 2;
  }
  return poses;
}

std::vector<Rigid2d> NoisyOdometry(const std::vector<Rigid2d>& truth, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Rigid2d> odometry = {truth.front()};
  for (size_t i = 1; i < truth.size(); ++i) {
    const Rigid2d step = truth[i - 1].inverse() * truth[i];
    const double d = step.translation().norm();
    const Rigid2d noisy(step.x() * (1.0 + 0.03 * noise(rng)), step.y() + 0.01 * d * noise(rng),
                        step.rotation() + 0.5 * (M_PI / 180.0) * d + 0.02 * std::abs(step.rotation()) * noise(rng));
    odometry.push_back(odometry.back() * noisy);
  }
  return odometry;
}

}  // namespace fleetmap::testing
