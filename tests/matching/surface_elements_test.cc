#include "shared/matching/surface_elements.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

constexpr double kResolution = 0.05;

// Points every `spacing` metres along a line through `start` with heading `angle`.
std::vector<Eigen::Vector2d> LinePoints(const Eigen::Vector2d& start, double angle, double spacing,
                                        int count) {
  std::vector<Eigen::Vector2d> points;
  const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
  for (int i = 0; i < count; ++i) points.push_back(start + i * spacing * direction);
  return points;
}

double DistanceToLine(const Eigen::Vector2d& p, const Eigen::Vector2d& start, double angle) {
  const Eigen::Vector2d normal(-std::sin(angle), std::cos(angle));
  return std::abs(normal.dot(p - start));
}

TEST(SurfaceElementsTest, PointsOnAWallBecomePiecesOfThatWall) {
  for (double angle : {0.0, 0.3, M_PI / 2, 2.5}) {
    const Eigen::Vector2d start(1.3, -0.7);
    const std::vector<Eigen::Vector2d> points = LinePoints(start, angle, 0.03, 30);
    const std::vector<SurfaceElement> elements = FitSurfaceElements(points, kResolution, SurfaceFitOptions());
    ASSERT_EQ(elements.size(), points.size());
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    for (size_t i = 0; i < elements.size(); ++i) {
      const SurfaceElement& e = elements[i];
      EXPECT_NEAR(std::abs(e.tangent.dot(direction)), 1.0, 1e-9) << angle << " " << i;
      EXPECT_LT(DistanceToLine(e.centre, start, angle), 1e-9);
      // The two ends reach nowhere outwards; every other element reaches a cell towards
      // each neighbour (they are 3 cm apart, closer than a cell).
      const bool forward = e.tangent.dot(direction) > 0.0;
      const double towards_start = forward ? e.extent_minus : e.extent_plus;
      const double towards_end = forward ? e.extent_plus : e.extent_minus;
      EXPECT_NEAR(towards_start, i == 0 ? 0.0 : std::min(kResolution, 0.03 * static_cast<double>(i)), 1e-9) << i;
      EXPECT_NEAR(towards_end, i + 1 == elements.size() ? 0.0 : std::min(kResolution, 0.03 * static_cast<double>(29 - i)), 1e-9) << i;
    }
  }
}

TEST(SurfaceElementsTest, NoisyWallPointsMoveOntoTheFittedWall) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Eigen::Vector2d> points = LinePoints(Eigen::Vector2d(0.0, 2.0), 0.0, 0.02, 60);
  for (Eigen::Vector2d& p : points) p.y() += noise(rng);
  const std::vector<SurfaceElement> elements = FitSurfaceElements(points, kResolution, SurfaceFitOptions());
  double raw = 0.0, fitted = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    raw += std::pow(points[i].y() - 2.0, 2);
    fitted += std::pow(elements[i].centre.y() - 2.0, 2);
  }
  EXPECT_LT(fitted, 0.25 * raw);
}

TEST(SurfaceElementsTest, SparselySampledWallPiecesMeetHalfway) {
  const std::vector<Eigen::Vector2d> points = LinePoints(Eigen::Vector2d(0.0, 0.0), 0.0, 0.14, 3);
  const std::vector<SurfaceElement> elements = FitSurfaceElements(points, kResolution, SurfaceFitOptions());
  for (size_t i = 1; i + 1 < elements.size(); ++i) {
    EXPECT_NEAR(elements[i].extent_minus, 0.07, 1e-9);
    EXPECT_NEAR(elements[i].extent_plus, 0.07, 1e-9);
  }
}

TEST(SurfaceElementsTest, CornersPolesAndLonePointsStayPoints) {
  // An L: the corner's neighbourhood spans both arms.
  std::vector<Eigen::Vector2d> points = LinePoints(Eigen::Vector2d(0.0, 0.0), 0.0, 0.02, 20);
  const std::vector<Eigen::Vector2d> arm = LinePoints(Eigen::Vector2d(0.0, 0.02), M_PI / 2, 0.02, 20);
  points.insert(points.end(), arm.begin(), arm.end());
  points.emplace_back(5.0, 5.0);  // alone
  points.emplace_back(5.3, 5.0);  // two points are not yet a wall
  points.emplace_back(5.32, 5.0);
  const std::vector<SurfaceElement> elements = FitSurfaceElements(points, kResolution, SurfaceFitOptions());
  EXPECT_EQ(elements[0].tangent, Eigen::Vector2d::Zero());
  EXPECT_EQ(elements[0].centre, points[0]);
  for (size_t i = points.size() - 3; i < points.size(); ++i) {
    EXPECT_EQ(elements[i].tangent, Eigen::Vector2d::Zero()) << i;
    EXPECT_EQ(elements[i].extent_minus + elements[i].extent_plus, 0.0);
  }
  // Far along an arm the neighbourhood is straight again.
  EXPECT_NEAR(std::abs(elements[19].tangent.x()), 1.0, 1e-9);
}

TEST(SurfaceElementsTest, ZeroRadiusKeepsEveryPointAPoint) {
  SurfaceFitOptions options;
  options.radius = 0.0;
  const std::vector<Eigen::Vector2d> points = LinePoints(Eigen::Vector2d(0.0, 0.0), 0.0, 0.02, 10);
  for (const SurfaceElement& e : FitSurfaceElements(points, kResolution, options)) {
    EXPECT_EQ(e.tangent, Eigen::Vector2d::Zero());
  }
}

TEST(SurfaceElementsTest, FarAwayPointsAreLeftAsPoints) {
  std::vector<Eigen::Vector2d> points = LinePoints(Eigen::Vector2d(1e9, 0.0), 0.0, 0.02, 10);
  for (const SurfaceElement& e : FitSurfaceElements(points, kResolution, SurfaceFitOptions())) {
    EXPECT_EQ(e.tangent, Eigen::Vector2d::Zero());
  }
}

}  // namespace
}  // namespace fleetmap
