#include "shared/core/relative_pose_residual.h"

#include <cmath>

#include <gtest/gtest.h>

namespace fleetmap {
namespace {

TEST(WrapAngleTest, WrapsIntoMinusPiToPi) {
  EXPECT_NEAR(WrapAngle(0.5), 0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(2.0 * M_PI + 0.5), 0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(-2.0 * M_PI - 0.5), -0.5, 1e-12);
  EXPECT_NEAR(WrapAngle(M_PI + 0.1), -M_PI + 0.1, 1e-12);
  EXPECT_NEAR(WrapAngle(M_PI), -M_PI, 1e-12);
}

// Two poses whose relation is known, their headings on either side of the +-pi seam: the
// residual vanishes at the relation and counts sigmas off it.
TEST(RelativePoseResidualTest, ZeroAtTheMeasurementAndInSigmasOffIt) {
  const Rigid2d from(1.0, 2.0, 3.1), to(-4.0, 0.5, -3.1);
  const Rigid2d to_in_from = from.inverse() * to;
  const double a[3] = {from.x(), from.y(), from.rotation()};
  const double b[3] = {to.x(), to.y(), to.rotation()};
  double residual[3];
  RelativePoseResidual(a, b, to_in_from, 0.1, 0.01, residual);
  for (double r : residual) EXPECT_NEAR(r, 0.0, 1e-9);

  // Measured 0.2 m further along from's x axis, 0.05 m along its y, and 0.02 rad more turned.
  const Rigid2d measured(to_in_from.translation() + Eigen::Vector2d(0.2, 0.05),
                         to_in_from.rotation() + 0.02);
  RelativePoseResidual(a, b, measured, 0.1, 0.01, residual);
  EXPECT_NEAR(residual[0], -2.0, 1e-9);
  EXPECT_NEAR(residual[1], -0.5, 1e-9);
  EXPECT_NEAR(residual[2], -2.0, 1e-9);
}

}  // namespace
}  // namespace fleetmap
