#include "map_server/merge/log_odds_canvas.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

constexpr int kGrowthBlock = 128;
constexpr float kZero = 1e-4f;  // sums this small are add/subtract round-off: unknown

int FloorDiv(int v, int block) { return static_cast<int>(std::floor(static_cast<double>(v) / block)) * block; }

}  // namespace

float LogOddsCanvas::Sum(int i, int j) const {
  const int x = i - min_cell_.x(), y = j - min_cell_.y();
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
  return sums_[static_cast<size_t>(y) * width_ + x];
}

void LogOddsCanvas::Add(int i, int j, float value) {
  GrowToInclude(Eigen::Array2i(i, j), Eigen::Array2i(i, j));
  sums_[static_cast<size_t>(j - min_cell_.y()) * width_ + (i - min_cell_.x())] += value;
}

void LogOddsCanvas::GrowToInclude(const Eigen::Array2i& lo, const Eigen::Array2i& hi) {
  const Eigen::Array2i max_cell = min_cell_ + Eigen::Array2i(width_, height_);  // exclusive
  if (!empty() && (lo >= min_cell_).all() && (hi < max_cell).all()) return;
  Eigen::Array2i new_min = lo, new_max = hi + 1;
  if (!empty()) {
    new_min = new_min.min(min_cell_);
    new_max = new_max.max(max_cell);
  }
  new_min = Eigen::Array2i(FloorDiv(new_min.x(), kGrowthBlock), FloorDiv(new_min.y(), kGrowthBlock));
  new_max = Eigen::Array2i(FloorDiv(new_max.x() + kGrowthBlock - 1, kGrowthBlock),
                           FloorDiv(new_max.y() + kGrowthBlock - 1, kGrowthBlock));
  const int w = new_max.x() - new_min.x(), h = new_max.y() - new_min.y();
  std::vector<float> sums(static_cast<size_t>(w) * h, 0.0f);
  for (int y = 0; y < height_; ++y) {
    const int ny = y + min_cell_.y() - new_min.y();
    std::copy_n(sums_.begin() + static_cast<long>(y) * width_, width_,
                sums.begin() + static_cast<long>(ny) * w + (min_cell_.x() - new_min.x()));
  }
  min_cell_ = new_min;
  width_ = w;
  height_ = h;
  sums_ = std::move(sums);
}

std::optional<Box2d> PlacedBounds(const OccupancyGrid& submap, const Rigid2d& submap_to_frame) {
  CellIndex lo, hi;
  if (!submap.KnownBounds(&lo, &hi)) return std::nullopt;
  const double r = submap.resolution();
  const Eigen::Vector2d a = submap.origin() + r * lo.cast<double>().matrix();
  const Eigen::Vector2d b = submap.origin() + r * (hi + 1).cast<double>().matrix();
  Box2d box{Eigen::Vector2d::Constant(1e300), Eigen::Vector2d::Constant(-1e300)};
  for (const Eigen::Vector2d& corner :
       {a, b, Eigen::Vector2d(a.x(), b.y()), Eigen::Vector2d(b.x(), a.y())}) {
    const Eigen::Vector2d p = submap_to_frame * corner;
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

void LogOddsCanvas::AddSubmap(const OccupancyGrid& submap, const Rigid2d& submap_to_frame,
                              float weight) {
  const auto box = PlacedBounds(submap, submap_to_frame);
  if (!box) return;
  const Eigen::Array2i lo((box->min / resolution_).array().floor().cast<int>());
  const Eigen::Array2i hi((box->max / resolution_).array().floor().cast<int>());
  GrowToInclude(lo, hi);
  // Supersample so that no submap cell is skipped when the canvas is coarser than the submap.
  const int samples = std::max(1, static_cast<int>(std::ceil(resolution_ / submap.resolution() - 1e-9)));
  const Rigid2d frame_to_submap = submap_to_frame.inverse();
  const Eigen::Matrix2d rot = frame_to_submap.rotation_matrix();
  const double inv_res = 1.0 / submap.resolution();
  const std::vector<float>& cells = submap.log_odds();
  for (int j = lo.y(); j <= hi.y(); ++j) {
    for (int i = lo.x(); i <= hi.x(); ++i) {
      float most = 0.0f, least = 0.0f;
      for (int sy = 0; sy < samples; ++sy) {
        for (int sx = 0; sx < samples; ++sx) {
          const Eigen::Vector2d p((i + (sx + 0.5) / samples) * resolution_,
                                  (j + (sy + 0.5) / samples) * resolution_);
          const Eigen::Vector2d q = (rot * p + frame_to_submap.translation() - submap.origin()) * inv_res;
          const int cx = static_cast<int>(std::floor(q.x())), cy = static_cast<int>(std::floor(q.y()));
          if (cx < 0 || cy < 0 || cx >= submap.width() || cy >= submap.height()) continue;
          const float v = cells[static_cast<size_t>(cy) * submap.width() + cx];
          most = std::max(most, v);
          least = std::min(least, v);
        }
      }
      const float value = most > 0.0f ? most : least;
      if (value != 0.0f) {
        sums_[static_cast<size_t>(j - min_cell_.y()) * width_ + (i - min_cell_.x())] += weight * value;
      }
    }
  }
}

void LogOddsCanvas::AddCanvas(const LogOddsCanvas& other, const std::optional<Box2d>& box) {
  if (other.empty()) return;
  Eigen::Array2i lo = other.min_cell_, hi = other.min_cell_ + Eigen::Array2i(other.width_, other.height_) - 1;
  if (box) {
    lo = lo.max(Eigen::Array2i((box->min / resolution_).array().floor().cast<int>()));
    hi = hi.min(Eigen::Array2i((box->max / resolution_).array().ceil().cast<int>()) - 1);
  }
  if ((hi < lo).any()) return;
  GrowToInclude(lo, hi);
  for (int j = lo.y(); j <= hi.y(); ++j) {
    const float* src = &other.sums_[static_cast<size_t>(j - other.min_cell_.y()) * other.width_ +
                                    (lo.x() - other.min_cell_.x())];
    float* dst = &sums_[static_cast<size_t>(j - min_cell_.y()) * width_ + (lo.x() - min_cell_.x())];
    for (int k = 0; k <= hi.x() - lo.x(); ++k) dst[k] += src[k];
  }
}

Box2d LogOddsCanvas::Extent() const {
  if (empty()) return Box2d();
  return Box2d{resolution_ * min_cell_.cast<double>().matrix(),
               resolution_ * (min_cell_ + Eigen::Array2i(width_, height_)).cast<double>().matrix()};
}

OccupancyGrid LogOddsCanvas::ToGrid(const OccupancyGridOptions& options,
                                    const std::optional<Box2d>& box) const {
  OccupancyGridOptions grid_options = options;
  grid_options.resolution = resolution_;
  Eigen::Array2i lo = min_cell_, hi = min_cell_ + Eigen::Array2i(width_, height_) - 1;
  if (box) {
    lo = Eigen::Array2i((box->min / resolution_).array().floor().cast<int>());
    hi = Eigen::Array2i((box->max / resolution_).array().ceil().cast<int>()) - 1;
  }
  if (empty() || (hi < lo).any()) return OccupancyGrid(grid_options);
  OccupancyGrid grid(grid_options, resolution_ * lo.cast<double>().matrix(), hi.x() - lo.x() + 1,
                     hi.y() - lo.y() + 1);
  for (int j = lo.y(); j <= hi.y(); ++j) {
    for (int i = lo.x(); i <= hi.x(); ++i) {
      const float sum = Sum(i, j);
      if (std::abs(sum) < kZero) continue;
      grid.SetLogOdds(CellIndex(i - lo.x(), j - lo.y()),
                      std::clamp(sum, options.log_odds_min, options.log_odds_max));
    }
  }
  return grid;
}

void Include(std::optional<Box2d>* region, const std::optional<Box2d>& box) {
  if (!box) return;
  if (!*region) {
    *region = box;
    return;
  }
  (*region)->min = (*region)->min.cwiseMin(box->min);
  (*region)->max = (*region)->max.cwiseMax(box->max);
}

}  // namespace fleetmap
