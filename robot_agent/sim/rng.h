#ifndef FLEETMAP_ROBOT_AGENT_SIM_RNG_H_
#define FLEETMAP_ROBOT_AGENT_SIM_RNG_H_

#include <cmath>
#include <cstdint>

namespace fleetmap::sim {

// A small seeded generator (splitmix64 + Box-Muller). We do not use <random>'s distributions
// because their output differs between standard libraries; the simulator promises the same files
// for the same seed.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}

  // Independent stream for a (seed, stream) pair, e.g. one per robot and sensor.
  static Rng ForStream(uint64_t seed, uint64_t stream) {
    Rng mixer(seed ^ (0x9E3779B97F4A7C15ULL * (stream + 1)));
    return Rng(mixer.Next());
  }

  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * (1.0 / 9007199254740992.0); }
  // Standard normal.
  double Gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = Uniform();
    if (u1 < 1e-300) u1 = 1e-300;
    const double u2 = Uniform();
    const double radius = std::sqrt(-2.0 * std::log(u1));
    spare_ = radius * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return radius * std::cos(2.0 * M_PI * u2);
  }
  double Gaussian(double sigma) { return sigma > 0.0 ? sigma * Gaussian() : 0.0; }

 private:
  uint64_t state_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_RNG_H_
