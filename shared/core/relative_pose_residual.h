#ifndef FLEETMAP_SHARED_CORE_RELATIVE_POSE_RESIDUAL_H_
#define FLEETMAP_SHARED_CORE_RELATIVE_POSE_RESIDUAL_H_

#include <cmath>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// The edge both pose graphs share (local SLAM's loop closures, the server's global graph).
// Templated on the scalar so that Ceres' automatic differentiation can evaluate it on its Jet
// type: cos, sin and floor are called unqualified and found by argument-dependent lookup, which
// keeps this library free of Ceres.

// Wraps an angle into [-pi, pi).
template <typename T>
T WrapAngle(const T& angle) {
  using std::floor;
  const T two_pi(2.0 * M_PI);
  return angle - two_pi * floor((angle + T(M_PI)) / two_pi);
}

// The measured pose of `to` in `from` against the one the two poses ({x, y, theta} each) imply,
// in units of the measurement's standard deviations.
template <typename T>
void RelativePoseResidual(const T* from, const T* to, const Rigid2d& to_in_from,
                          double translation_sigma, double rotation_sigma, T* residual) {
  using std::cos;
  using std::sin;
  const T c = cos(from[2]), s = sin(from[2]);
  const T dx = to[0] - from[0], dy = to[1] - from[1];
  residual[0] = (c * dx + s * dy - T(to_in_from.x())) / T(translation_sigma);
  residual[1] = (-s * dx + c * dy - T(to_in_from.y())) / T(translation_sigma);
  residual[2] = WrapAngle(to[2] - from[2] - T(to_in_from.rotation())) / T(rotation_sigma);
}

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_RELATIVE_POSE_RESIDUAL_H_
