#include "robot_agent/slam/return_persistence.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

constexpr double kDegree = M_PI / 180.0;

// What a robot at (x, 0) sees of a wall along y = 2: one return per degree of bearing from 5 to
// 175 degrees, so that far along the wall they are up to half a metre apart.
std::vector<Eigen::Vector2d> Wall(double x) {
  std::vector<Eigen::Vector2d> points;
  for (int degrees = 5; degrees <= 175; ++degrees) {
    const double bearing = degrees * kDegree;
    const double along = 2.0 / std::tan(bearing);
    if (std::abs(along) < 12.0) points.emplace_back(x + along, 2.0);
  }
  return points;
}

// The back of a 0.4 m wide body at x, right ahead (in beam order, like the wall).
std::vector<Eigen::Vector2d> BodyBack(double x) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 8; ++i) points.emplace_back(x, -0.2 + 0.05 * i);
  return points;
}

int Count(const std::vector<bool>& flags, size_t begin, size_t end) {
  int n = 0;
  for (size_t i = begin; i < end; ++i) n += flags[i] ? 1 : 0;
  return n;
}

TEST(ReturnPersistenceTest, TheFirstScanPassesWhole) {
  ReturnPersistence persistence;
  const std::vector<bool> kept = persistence.Observe(BodyBack(3.0), Eigen::Vector2d::Zero());
  EXPECT_EQ(Count(kept, 0, kept.size()), 9);
}

// The robot drives along the wall at 0.08 m per scan with another robot 3 m ahead at its speed:
// every return off the wall persists, even 8 m down it where the beams hit new spots 0.6 m
// apart, and none off the other robot's back. (Farther still, 1 m apart, the returns are no
// longer taken for one surface.)
TEST(ReturnPersistenceTest, AWallPersistsAndABodyMovingAheadNever) {
  ReturnPersistence persistence;
  int wall_returns = 0, wall_kept = 0, body_kept = 0;
  for (int scan = 0; scan < 30; ++scan) {
    const double x = 0.08 * scan;
    std::vector<Eigen::Vector2d> points = BodyBack(x + 3.0);
    const size_t body = points.size();
    const std::vector<Eigen::Vector2d> wall = Wall(x);
    points.insert(points.end(), wall.begin(), wall.end());
    const std::vector<bool> kept = persistence.Observe(points, Eigen::Vector2d(x, 0.0));
    if (scan == 0) continue;
    for (size_t i = 0; i < wall.size(); ++i) {
      if (std::abs(wall[i].x() - x) > 8.0) continue;
      ++wall_returns;
      wall_kept += kept[body + i] ? 1 : 0;
    }
    body_kept += Count(kept, 0, body);
  }
  EXPECT_EQ(wall_kept, wall_returns);
  EXPECT_EQ(body_kept, 0);
}

TEST(ReturnPersistenceTest, ABodyThatStopsPersistsFromTheNextScan) {
  ReturnPersistence persistence;
  const Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  persistence.Observe(BodyBack(3.0), origin);
  const std::vector<bool> moved = persistence.Observe(BodyBack(2.9), origin);
  EXPECT_EQ(Count(moved, 0, moved.size()), 0);
  const std::vector<bool> stopped = persistence.Observe(BodyBack(2.9), origin);
  EXPECT_EQ(Count(stopped, 0, stopped.size()), 9);
  // Range noise well below the tolerance (3 cm) does not matter.
  std::vector<Eigen::Vector2d> noisy = BodyBack(2.9);
  for (size_t i = 0; i < noisy.size(); ++i) noisy[i].x() += (i % 2 == 0 ? 0.015 : -0.015);
  const std::vector<bool> kept = persistence.Observe(noisy, origin);
  EXPECT_EQ(Count(kept, 0, kept.size()), 9);
}

TEST(ReturnPersistenceTest, ZeroToleranceKeepsEverythingAndNonFiniteReturnsNever) {
  ReturnPersistenceOptions options;
  options.tolerance = 0.0;
  ReturnPersistence all(options);
  all.Observe(BodyBack(3.0), Eigen::Vector2d::Zero());
  const std::vector<bool> moved = all.Observe(BodyBack(2.0), Eigen::Vector2d::Zero());
  EXPECT_EQ(Count(moved, 0, moved.size()), 9);

  ReturnPersistence persistence;
  persistence.Observe(BodyBack(3.0), Eigen::Vector2d::Zero());
  const std::vector<bool> kept =
      persistence.Observe({Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(NAN, 0.0)}, Eigen::Vector2d::Zero());
  EXPECT_TRUE(kept[0]);
  EXPECT_FALSE(kept[1]);
}

// Asking at a predicted pose does not replace the scan the next one is judged against.
TEST(ReturnPersistenceTest, AskingDoesNotRecord) {
  ReturnPersistence persistence;
  const Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  persistence.Observe(BodyBack(3.0), origin);
  const std::vector<bool> moved = persistence.Persisted(BodyBack(2.9));
  EXPECT_EQ(Count(moved, 0, moved.size()), 0);
  const std::vector<bool> asked = persistence.Persisted(BodyBack(3.0));
  EXPECT_EQ(Count(asked, 0, asked.size()), 9);
  const std::vector<bool> observed = persistence.Observe(BodyBack(3.0), origin);
  EXPECT_EQ(Count(observed, 0, observed.size()), 9);
}

}  // namespace
}  // namespace fleetmap
