#ifndef FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_RATE_BENCHMARK_H_
#define FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_RATE_BENCHMARK_H_

namespace fleetmap {

struct RateBenchmarkOptions {
  int particles = 5000;
  int beams = 60;
  int updates = 300;
};

struct RateBenchmarkResult {
  double seconds = 0.0;
  double updates_per_second = 0.0;
  double updates_per_second_with_resampling = 0.0;
};

// Times Predict + UpdateLaser on a synthetic 30 m x 20 m office map with a 181-beam scan, the
// particle count held fixed. Single thread.
RateBenchmarkResult RunRateBenchmark(const RateBenchmarkOptions& options);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_LOCALIZATION_TOOL_RATE_BENCHMARK_H_
