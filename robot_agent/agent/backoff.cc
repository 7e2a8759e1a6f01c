#include "robot_agent/agent/backoff.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

double BackoffDelay(const BackoffOptions& options, int attempt, double unit_random) {
  const double cap = std::max(0.0, options.max);
  const double initial = std::clamp(options.initial, 0.0, cap);
  const double multiplier = std::max(1.0, options.multiplier);
  // Grow step by step and stop at the cap, so that large attempt counts cannot overflow.
  double delay = initial;
  for (int i = 1; i < attempt && delay < cap; ++i) delay *= multiplier;
  delay = std::min(delay, cap);
  const double jitter = std::clamp(options.jitter, 0.0, 1.0);
  const double u = std::clamp(unit_random, 0.0, 1.0);
  return delay * (1.0 - jitter * u);
}

}  // namespace fleetmap
