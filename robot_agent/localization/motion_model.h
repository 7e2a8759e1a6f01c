#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_MOTION_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_MOTION_MODEL_H_

#include <random>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// Noise of Thrun's odometry motion model (Probabilistic Robotics, table 5.6). The increment is
// split into rotate (rot1), translate (trans), rotate (rot2); each part gets zero-mean Gaussian
// noise whose variance grows with the motion.
struct OdometryMotionModelOptions {
  double alpha1 = 0.05;  // rotation noise from rotation (rad^2 / rad^2)
  double alpha2 = 0.02;  // rotation noise from translation (rad^2 / m^2)
  double alpha3 = 0.05;  // translation noise from translation (m^2 / m^2)
  double alpha4 = 0.02;  // translation noise from rotation (m^2 / rad^2)
  // Floors so that a robot standing still still diffuses a little (keeps diversity).
  double min_translation_std = 0.0;  // metres per update
  double min_rotation_std = 0.0;     // radians per update
};

// The odometry increment split into Thrun's three parts. A step whose direction points backward
// is treated as reverse driving (negative translation), as AMCL does, so that a robot that
// backs up does not turn by pi twice.
struct OdometryParts {
  double rot1 = 0.0;
  double trans = 0.0;
  double rot2 = 0.0;
};
OdometryParts DecomposeOdometry(const Rigid2d& odometry_delta);

// Precomputes the noise scales of one increment so that many particles can be moved cheaply.
class OdometrySampler {
 public:
  OdometrySampler(const Rigid2d& odometry_delta, const OdometryMotionModelOptions& options);
  // Returns `robot_in_map` moved by a noisy version of the increment.
  Rigid2d Sample(const Rigid2d& robot_in_map, std::mt19937& rng) const;

 private:
  OdometryParts parts_;
  double rot1_std_ = 0.0;
  double trans_std_ = 0.0;
  double rot2_std_ = 0.0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_MOTION_MODEL_H_
