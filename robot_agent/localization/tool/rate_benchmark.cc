#include "robot_agent/localization/tool/rate_benchmark.h"

#include <chrono>
#include <cmath>

#include "robot_agent/localization/mcl.h"
#include "shared/core/likelihood_field.h"

namespace fleetmap {
namespace {

OccupancyGrid OfficeGrid() {
  OccupancyGridOptions options;
  OccupancyGrid grid(options, Eigen::Vector2d(0, 0), 600, 400);
  for (int y = 0; y < 400; ++y) {
    for (int x = 0; x < 600; ++x) {
      const bool outer = x < 2 || y < 2 || x >= 598 || y >= 398;
      // Inner walls every 6 m with 1 m doors, and a corridor wall at y = 10 m.
      const bool inner = (x % 120 < 2 && (y < 180 || y > 220) && y % 100 > 20);
      const bool corridor = (y >= 198 && y < 202 && x % 120 > 30);
      grid.SetLogOdds(CellIndex(x, y),
                      outer || inner || corridor ? options.log_odds_max : options.log_odds_min);
    }
  }
  return grid;
}

LaserScan RayCast(const OccupancyGrid& grid, const Rigid2d& pose) {
  std::vector<float> ranges;
  for (int i = 0; i < 181; ++i) {
    const double a = pose.rotation() - M_PI / 2 + i * M_PI / 180;
    float range = LaserScan::kNoReturn;
    for (double r = 0.05; r < 8.0; r += 0.02) {
      const Eigen::Vector2d p = pose.translation() + r * Eigen::Vector2d(std::cos(a), std::sin(a));
      if (grid.Probability(grid.CellAt(p)) > 0.6f) {
        range = static_cast<float>(r);
        break;
      }
    }
    ranges.push_back(range);
  }
  return MakeLaserScan(0.0, static_cast<float>(-M_PI / 2), static_cast<float>(M_PI / 180), 0.0f,
                       8.0f, ranges);
}

}  // namespace

RateBenchmarkResult RunRateBenchmark(const RateBenchmarkOptions& options) {
  const OccupancyGrid grid = OfficeGrid();
  const LikelihoodField field(grid, LikelihoodFieldOptions());
  LikelihoodFieldModelOptions model_options;
  model_options.max_beams = options.beams;
  LikelihoodFieldModel model(field, model_options);
  MclOptions mcl_options;
  mcl_options.kld.min_particles = mcl_options.kld.max_particles = options.particles;
  const Rigid2d truth(3.0, 5.0, 0.3);
  const LaserScan scan = RayCast(grid, truth);
  const Rigid2d step(0.05, 0.0, 0.01);
  RateBenchmarkResult result;
  for (const bool force_resampling : {false, true}) {
    Mcl mcl(FreeSpace::FromGrid(grid), mcl_options);
    mcl.InitializeGaussian(truth, Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal(),
                           options.particles);
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < options.updates; ++i) {
      mcl.Predict(step);
      mcl.UpdateLaser(scan, model);
      if (force_resampling) mcl.Resample();
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!force_resampling) {
      result.seconds = seconds;
      result.updates_per_second = options.updates / seconds;
    } else {
      result.updates_per_second_with_resampling = options.updates / seconds;
    }
  }
  return result;
}

}  // namespace fleetmap
