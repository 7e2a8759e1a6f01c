#include "shared/core/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>

namespace fleetmap {
namespace {

// Grids grow in whole blocks so that a robot driving along an edge does not reallocate per scan.
constexpr int kGrowthBlock = 64;

int RoundDownToBlock(int v) {
  return static_cast<int>(std::floor(static_cast<double>(v) / kGrowthBlock)) * kGrowthBlock;
}

}  // namespace

float ProbabilityToLogOdds(float probability) {
  return std::log(probability / (1.0f - probability));
}

OccupancyGrid::OccupancyGrid(const OccupancyGridOptions& options) : options_(options) {}

OccupancyGrid::OccupancyGrid(const OccupancyGridOptions& options, const Eigen::Vector2d& origin,
                             int width, int height)
    : options_(options),
      origin_(origin),
      width_(std::max(0, width)),
      height_(std::max(0, height)),
      cells_(static_cast<size_t>(width_) * static_cast<size_t>(height_), 0.0f) {}

CellIndex OccupancyGrid::CellAt(const Eigen::Vector2d& point_in_map) const {
  const Eigen::Vector2d rel = (point_in_map - origin_) / options_.resolution;
  return CellIndex(static_cast<int>(std::floor(rel.x())), static_cast<int>(std::floor(rel.y())));
}

Eigen::Vector2d OccupancyGrid::CellCenter(const CellIndex& cell) const {
  return origin_ + options_.resolution * (cell.cast<double>().matrix() + Eigen::Vector2d(0.5, 0.5));
}

bool OccupancyGrid::Contains(const CellIndex& cell) const {
  return cell.x() >= 0 && cell.y() >= 0 && cell.x() < width_ && cell.y() < height_;
}

float OccupancyGrid::LogOdds(const CellIndex& cell) const {
  return Contains(cell) ? cells_[static_cast<size_t>(Index(cell))] : 0.0f;
}

float OccupancyGrid::Probability(const CellIndex& cell) const {
  return LogOddsToProbability(LogOdds(cell));
}

void OccupancyGrid::SetLogOdds(const CellIndex& cell, float log_odds) {
  const CellIndex inside = EnsureContains(cell);
  cells_[static_cast<size_t>(Index(inside))] = log_odds;
}

void OccupancyGrid::AddLogOdds(const CellIndex& cell, float delta) {
  const CellIndex inside = EnsureContains(cell);
  UpdateCell(Index(inside), delta);
}

void OccupancyGrid::UpdateCell(int index, float delta) {
  float& value = cells_[static_cast<size_t>(index)];
  value = std::clamp(value + delta, options_.log_odds_min, options_.log_odds_max);
  // Exactly 0 means "never observed"; an observed cell that cancels out stays observed.
  if (value == 0.0f) value = delta > 0.0f ? 1e-6f : -1e-6f;
}

CellIndex OccupancyGrid::EnsureContains(const CellIndex& cell) {
  if (Contains(cell)) return cell;
  const Eigen::Vector2d center = CellCenter(cell);
  GrowToInclude(center, center);
  return CellAt(center);
}

void OccupancyGrid::GrowToInclude(const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
  const CellIndex lo = CellAt(min);
  const CellIndex hi = CellAt(max);
  if (!empty() && Contains(lo) && Contains(hi)) return;
  CellIndex new_min = lo;
  CellIndex new_max = hi + 1;  // exclusive
  if (!empty()) {
    new_min = new_min.min(CellIndex(0, 0));
    new_max = new_max.max(CellIndex(width_, height_));
  }
  new_min = CellIndex(RoundDownToBlock(new_min.x()), RoundDownToBlock(new_min.y()));
  new_max = CellIndex(RoundDownToBlock(new_max.x() + kGrowthBlock - 1),
                      RoundDownToBlock(new_max.y() + kGrowthBlock - 1));
  Resize(new_min, new_max);
}

void OccupancyGrid::Resize(const CellIndex& new_min, const CellIndex& new_max) {
  const int new_width = new_max.x() - new_min.x();
  const int new_height = new_max.y() - new_min.y();
  std::vector<float> cells(static_cast<size_t>(new_width) * static_cast<size_t>(new_height), 0.0f);
  for (int y = 0; y < height_; ++y) {
    const int ny = y - new_min.y();
    std::copy_n(cells_.begin() + static_cast<long>(y) * width_, width_,
                cells.begin() + static_cast<long>(ny) * new_width - new_min.x());
  }
  origin_ += options_.resolution * new_min.cast<double>().matrix();
  width_ = new_width;
  height_ = new_height;
  cells_ = std::move(cells);
}

void OccupancyGrid::InsertScan(const LaserScan& scan, const Rigid2d& robot_in_map) {
  const Rigid2d sensor_in_map = robot_in_map * scan.sensor_in_robot;
  const float trace_limit = options_.max_trace_range > 0.0f
                                ? std::min(options_.max_trace_range, scan.range_max)
                                : scan.range_max;
  // Gather beam end points first so the grid grows once per scan, not once per beam.
  struct Beam {
    Eigen::Vector2d end;
    bool hit;
  };
  std::vector<Beam> beams;
  beams.reserve(scan.ranges.size());
  const Eigen::Vector2d origin = sensor_in_map.translation();
  Eigen::Vector2d lo = origin, hi = origin;
  for (int i = 0; i < scan.size(); ++i) {
    float range = scan.ranges[static_cast<size_t>(i)];
    bool hit = true;
    if (!scan.IsReturn(i)) {
      if (options_.no_return_free_distance <= 0.0f || scan.IsMasked(i)) continue;
      range = std::min(options_.no_return_free_distance, trace_limit);
      hit = false;
    } else if (trace_limit > 0.0f && range > trace_limit) {
      range = trace_limit;
      hit = false;
    }
    const double a = static_cast<double>(scan.angle(i));
    const Eigen::Vector2d end = sensor_in_map * Eigen::Vector2d(range * std::cos(a), range * std::sin(a));
    beams.push_back({end, hit});
    lo = lo.cwiseMin(end);
    hi = hi.cwiseMax(end);
  }
  if (beams.empty()) return;
  GrowToInclude(lo, hi);

  const CellIndex start = CellAt(origin);
  for (const Beam& beam : beams) {
    const CellIndex end = CellAt(beam.end);
    // Bresenham from the sensor cell to the end cell, end cell excluded.
    int x = start.x(), y = start.y();
    const int dx = std::abs(end.x() - x), dy = -std::abs(end.y() - y);
    const int sx = x < end.x() ? 1 : -1, sy = y < end.y() ? 1 : -1;
    int err = dx + dy;
    while (x != end.x() || y != end.y()) {
      UpdateCell(y * width_ + x, options_.log_odds_miss);
      const int e2 = 2 * err;
      if (e2 >= dy) { err += dy; x += sx; }
      if (e2 <= dx) { err += dx; y += sy; }
    }
    UpdateCell(Index(end), beam.hit ? options_.log_odds_hit : options_.log_odds_miss);
  }
}

bool OccupancyGrid::KnownBounds(CellIndex* min_cell, CellIndex* max_cell) const {
  // Per row only the first and last known cells matter: searching from both ends stops at the
  // first hit, so a submap whose rows are known near their ends costs little more than a pass
  // over its rows (this runs for every submap the merge engine renders).
  CellIndex lo(width_, height_), hi(-1, -1);
  const auto known = [](float v) { return v != 0.0f; };
  for (int y = 0; y < height_; ++y) {
    const float* row = cells_.data() + static_cast<size_t>(y) * width_;
    const float* first = std::find_if(row, row + width_, known);
    if (first == row + width_) continue;
    const float* last = std::find_if(std::make_reverse_iterator(row + width_),
                                     std::make_reverse_iterator(first), known)
                            .base() -
                        1;
    lo = lo.min(CellIndex(static_cast<int>(first - row), y));
    hi = hi.max(CellIndex(static_cast<int>(last - row), y));
  }
  if (hi.x() < 0) return false;
  *min_cell = lo;
  *max_cell = hi;
  return true;
}

}  // namespace fleetmap
