#ifndef FLEETMAP_ROBOT_AGENT_AGENT_BACKOFF_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_BACKOFF_H_

namespace fleetmap {

// Exponential backoff with jitter and a cap, for retrying uploads and reconnecting streams.
struct BackoffOptions {
  double initial = 0.2;     // seconds before the first retry
  double multiplier = 2.0;  // growth per failed attempt, >= 1
  double max = 30.0;        // cap, seconds; the jittered delay never exceeds it
  // Each delay is shortened by a random fraction in [0, jitter) of itself, so that robots that
  // lost the server together do not all come back in the same instant. In [0, 1].
  double jitter = 0.2;
};

// The delay before retry number `attempt` (1 = after the first failure). `unit_random` is a
// draw from [0, 1) (the caller owns the random source, so tests can fix it). Never negative,
// never above options.max.
double BackoffDelay(const BackoffOptions& options, int attempt, double unit_random);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_BACKOFF_H_
