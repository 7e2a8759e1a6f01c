#include "robot_agent/detection/circle_fit.h"

#include <random>

#include <Eigen/Dense>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

// Exact returns of beams from the origin hitting a circle, every `step` radians.
std::vector<BeamReturn> BeamsOnCircle(const Eigen::Vector2d& center, double radius, double step,
                                      double noise = 0.0, unsigned seed = 1) {
  std::mt19937 engine(seed);
  std::normal_distribution<double> normal(0.0, noise > 0.0 ? noise : 1.0);
  std::vector<BeamReturn> beams;
  const double bearing = std::atan2(center.y(), center.x());
  const double half = std::asin(radius / center.norm());
  for (double a = bearing - half; a <= bearing + half; a += step) {
    const Eigen::Vector2d u(std::cos(a), std::sin(a));
    const double along = u.dot(center);
    const double q = radius * radius - center.squaredNorm() + along * along;
    if (q <= 0.0) continue;
    beams.push_back({u, along - std::sqrt(q) + (noise > 0.0 ? noise * normal(engine) : 0.0)});
  }
  return beams;
}

TEST(CircleFitTest, RecoversCentreFromExactReturns) {
  const Eigen::Vector2d center(3.0, 1.0);
  const auto fit = FitCircleKnownRadius(BeamsOnCircle(center, 0.2, M_PI / 180), 0.2);
  ASSERT_TRUE(fit);
  EXPECT_LT((fit->center - center).norm(), 1e-6);
  EXPECT_LT(fit->rms, 1e-6);
}

TEST(CircleFitTest, UncertaintyGrowsWithRangeAndShrinksWithReturns) {
  const auto near = FitCircleKnownRadius(BeamsOnCircle({2.0, 0.0}, 0.2, M_PI / 180), 0.2);
  const auto far = FitCircleKnownRadius(BeamsOnCircle({6.0, 0.0}, 0.2, M_PI / 180), 0.2);
  const auto dense = FitCircleKnownRadius(BeamsOnCircle({6.0, 0.0}, 0.2, M_PI / 720), 0.2);
  ASSERT_TRUE(near && far && dense);
  EXPECT_GT(far->information.inverse().trace(), near->information.inverse().trace());
  EXPECT_LT(dense->information.inverse().trace(), far->information.inverse().trace());
}

TEST(CircleFitTest, NoisyFitIsWithinItsCovariance) {
  const Eigen::Vector2d center(4.0, -1.0);
  int inside = 0;
  for (unsigned seed = 1; seed <= 200; ++seed) {
    const auto fit = FitCircleKnownRadius(BeamsOnCircle(center, 0.2, M_PI / 360, 0.01, seed), 0.2);
    ASSERT_TRUE(fit);
    const Eigen::Vector2d e = fit->center - center;
    const Eigen::Matrix2d covariance = 1e-4 * fit->information.inverse();
    if (e.dot(covariance.inverse() * e) <= 5.991) ++inside;
  }
  EXPECT_GT(inside, 175);  // ~95 % expected
}

TEST(CircleFitTest, DegenerateInputs) {
  EXPECT_FALSE(FitCircleKnownRadius({}, 0.2));
  EXPECT_FALSE(FitCircleKnownRadius({BeamReturn{{1.0, 0.0}, 2.0}}, 0.2));
  EXPECT_FALSE(FitCircleKnownRadius(BeamsOnCircle({3.0, 0.0}, 0.2, 0.01), -1.0));
  std::vector<BeamReturn> bad = {{{1.0, 0.0}, 2.0}, {{0.0, 1.0}, std::nan("")}};
  EXPECT_FALSE(FitCircleKnownRadius(bad, 0.2));
}

TEST(CircleFitTest, LineFitSeparatesFlatFromRound) {
  std::vector<BeamReturn> wall;
  for (int i = -3; i <= 3; ++i) {
    const double a = i * M_PI / 180;
    wall.push_back({{std::cos(a), std::sin(a)}, 3.0 / std::cos(a)});
  }
  EXPECT_LT(LineFitRms(wall), 1e-9);
  EXPECT_GT(LineFitRms(BeamsOnCircle({3.0, 0.0}, 0.2, M_PI / 360)), 0.005);
}

}  // namespace
}  // namespace fleetmap
