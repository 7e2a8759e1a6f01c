#include "robot_agent/bench/map_extent.h"

#include <algorithm>
#include <vector>

namespace fleetmap {
namespace {

double Median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// Position of the outermost wall on one side of `values` (sorted ascending): low or high end.
double OuterWall(const std::vector<double>& sorted, bool low, const MapExtentOptions& options) {
  const size_t n = sorted.size();
  const size_t k = std::min(n - 1, static_cast<size_t>(options.quantile * static_cast<double>(n)));
  const double extreme = low ? sorted[k] : sorted[n - 1 - k];
  std::vector<double> band;
  for (double v : sorted) {
    if (low ? (v <= extreme + options.band && v >= extreme - options.band)
            : (v >= extreme - options.band && v <= extreme + options.band)) {
      band.push_back(v);
    }
  }
  return Median(band);
}

}  // namespace

std::optional<MapExtent> MeasureOuterWalls(const OccupancyGrid& map, const Rigid2d& world_from_map,
                                           const MapExtentOptions& options) {
  std::vector<Eigen::Vector2d> occupied;
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      const CellIndex cell(x, y);
      if (map.Probability(cell) > options.occupied_probability) {
        occupied.push_back(world_from_map * map.CellCenter(cell));
      }
    }
  }
  return MeasureOuterWalls(occupied, options);
}

std::optional<MapExtent> MeasureOuterWalls(const std::vector<Eigen::Vector2d>& points,
                                           const MapExtentOptions& options) {
  if (points.empty()) return std::nullopt;
  std::vector<double> xs, ys;
  xs.reserve(points.size());
  ys.reserve(points.size());
  for (const Eigen::Vector2d& p : points) {
    xs.push_back(p.x());
    ys.push_back(p.y());
  }
  std::sort(xs.begin(), xs.end());
  std::sort(ys.begin(), ys.end());
  MapExtent extent;
  extent.min = Eigen::Vector2d(OuterWall(xs, true, options), OuterWall(ys, true, options));
  extent.max = Eigen::Vector2d(OuterWall(xs, false, options), OuterWall(ys, false, options));
  return extent;
}

}  // namespace fleetmap
