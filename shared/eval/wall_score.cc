#include "shared/eval/wall_score.h"

#include <algorithm>
#include <cmath>

#include "shared/eval/map_fit.h"
#include "shared/io/map_file.h"

namespace fleetmap {
namespace {

std::vector<Eigen::Vector2d> OccupiedCellCenters(const OccupancyGrid& map) {
  const float occupied = static_cast<float>(MapMetadata().occupied_thresh);
  std::vector<Eigen::Vector2d> centers;
  for (int y = 0; y < map.height(); ++y) {
    for (int x = 0; x < map.width(); ++x) {
      const CellIndex cell(x, y);
      if (map.Probability(cell) > occupied) centers.push_back(map.CellCenter(cell));
    }
  }
  return centers;
}

}  // namespace

WallMask::WallMask(const Eigen::Vector2d& origin, double resolution, int width, int height,
                   const std::vector<uint8_t>& wall, int reach)
    : origin_(origin),
      resolution_(resolution),
      width_(width),
      height_(height),
      near_(static_cast<size_t>(width) * height, 0) {
  // Dilate once here so that each query reads one cell.
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      if (!wall[static_cast<size_t>(y) * width_ + x]) continue;
      for (int ny = std::max(0, y - reach); ny <= std::min(height_ - 1, y + reach); ++ny) {
        for (int nx = std::max(0, x - reach); nx <= std::min(width_ - 1, x + reach); ++nx) {
          near_[static_cast<size_t>(ny) * width_ + nx] = 1;
        }
      }
    }
  }
}

WallMask WallMask::FromTrueMap(const OccupancyGrid& truth, int reach) {
  const float occupied = static_cast<float>(MapMetadata().occupied_thresh);
  std::vector<uint8_t> wall(static_cast<size_t>(truth.width()) * truth.height(), 0);
  for (int y = 0; y < truth.height(); ++y) {
    for (int x = 0; x < truth.width(); ++x) {
      wall[static_cast<size_t>(y) * truth.width() + x] =
          truth.Probability(CellIndex(x, y)) > occupied;
    }
  }
  return WallMask(truth.origin(), truth.resolution(), truth.width(), truth.height(), wall, reach);
}

bool WallMask::NearWall(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d local = (point - origin_) / resolution_;
  const double fx = std::floor(local.x());
  const double fy = std::floor(local.y());
  if (!(fx >= 0 && fy >= 0 && fx < width_ && fy < height_)) return false;
  return near_[static_cast<size_t>(fy) * width_ + static_cast<size_t>(fx)] != 0;
}

WallScore ScoreOnWalls(const OccupancyGrid& map, const Rigid2d& map_in_truth,
                       const WallMask& walls) {
  WallScore score;
  for (const Eigen::Vector2d& p : OccupiedCellCenters(map)) {
    ++score.occupied;
    score.near_wall += walls.NearWall(map_in_truth * p);
  }
  return score;
}

WallScore ScoreOnWallsBestFit(const OccupancyGrid& map, const Rigid2d& initial,
                              const WallMask& walls, Rigid2d* best) {
  const std::vector<Eigen::Vector2d> occupied = OccupiedCellCenters(map);
  const MapFit fit =
      FitMapToWalls(occupied, initial, [&](const Eigen::Vector2d& p) { return walls.NearWall(p); });
  if (best) *best = fit.placement;
  WallScore score;
  score.occupied = static_cast<int64_t>(occupied.size());
  score.near_wall = fit.on_wall;
  return score;
}

}  // namespace fleetmap
