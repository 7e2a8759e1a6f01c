#include "robot_agent/detection/relative_heading.h"

#include <cmath>

#include "shared/core/rigid2d.h"

namespace fleetmap {
namespace {

// Variance of the direction angle of a 2D point with covariance `cov`.
double AngleVariance(const Eigen::Vector2d& p, const Eigen::Matrix2d& cov) {
  const double r2 = p.squaredNorm();
  const Eigen::Vector2d jacobian(-p.y() / r2, p.x() / r2);
  return jacobian.dot(cov * jacobian);
}

}  // namespace

std::optional<RelativeHeading> MutualRelativeHeading(const RobotDetection& a_sees_b,
                                                     const RobotDetection& b_sees_a,
                                                     double max_time_difference) {
  if (a_sees_b.observer_id != b_sees_a.observed_id ||
      a_sees_b.observed_id != b_sees_a.observer_id) {
    return std::nullopt;
  }
  if (!(std::abs(a_sees_b.timestamp - b_sees_a.timestamp) <= max_time_difference)) {
    return std::nullopt;
  }
  const Eigen::Vector2d& b_in_a = a_sees_b.position_in_observer;
  const Eigen::Vector2d& a_in_b = b_sees_a.position_in_observer;
  constexpr double kMinRange = 0.05;
  if (!b_in_a.allFinite() || !a_in_b.allFinite() || b_in_a.norm() < kMinRange ||
      a_in_b.norm() < kMinRange) {
    return std::nullopt;
  }
  // R(heading) * a_in_b = -b_in_a, so heading = angle(-b_in_a) - angle(a_in_b).
  RelativeHeading result;
  result.heading = NormalizeAngle(std::atan2(-b_in_a.y(), -b_in_a.x()) -
                                  std::atan2(a_in_b.y(), a_in_b.x()));
  result.variance = AngleVariance(b_in_a, a_sees_b.covariance) +
                    AngleVariance(a_in_b, b_sees_a.covariance);
  return result;
}

}  // namespace fleetmap
