#ifndef FLEETMAP_SHARED_CORE_ROBOT_DETECTION_H_
#define FLEETMAP_SHARED_CORE_ROBOT_DETECTION_H_

#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Core>

namespace fleetmap {

// One robot seeing another: the Gaussian detection model. Produced by the agent's detection
// pipeline (camera marker + laser fit), uploaded to the server, consumed by the merge engine
// (as an inter-robot constraint) and by collaborative localization (eq. 15 of the paper).
struct RobotDetection {
  std::string observer_id;
  std::string observed_id;
  double timestamp = 0.0;  // seconds, the observer's scan time
  // The observed robot's centre in the observer's robot frame (metres).
  Eigen::Vector2d position_in_observer = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();
  // The observed robot's heading in the observer's robot frame, when known (e.g. both robots
  // saw each other at the same time), with its variance (rad^2).
  std::optional<double> relative_heading;
  double relative_heading_variance = 0.0;
  double confidence = 1.0;  // in [0, 1]
  // How the laser measured it (diagnostics of the detector; not sent to the server).
  int laser_returns = 0;  // returns used by the circle fit
  double fit_rms = 0.0;   // metres, range residual RMS of the fit

  double range() const { return position_in_observer.norm(); }
  // Radians, + to the left, in the observer's robot frame.
  double bearing() const { return std::atan2(position_in_observer.y(), position_in_observer.x()); }
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_ROBOT_DETECTION_H_
