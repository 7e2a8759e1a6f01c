#include "map_server/merge/log_odds_canvas.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

constexpr int kGrowthBlock = 128;
constexpr float kZero = 1e-4f;  // sums this small are add/subtract round-off: unknown

int FloorDiv(int v, int block) { return static_cast<int>(std::floor(static_cast<double>(v) / block)) * block; }

// Narrows [*first, *last] to the steps t of the line b + a * t that fall within [0, size),
// widened by one step on each side (the caller still checks every cell); *first > *last when
// none does.
void ClipLine(double b, double a, double size, int* first, int* last) {
  if (std::abs(a) < 1e-12) {
    if (b < 0.0 || b >= size) *first = *last + 1;
    return;
  }
  double t0 = (0.0 - b) / a, t1 = (size - b) / a;
  if (t0 > t1) std::swap(t0, t1);
  // Clamped in doubles first: a nearly flat line puts t0 and t1 beyond any int.
  const double lo = *first, hi = *last;
  *first = static_cast<int>(std::clamp(std::floor(t0) - 1.0, lo, hi + 1.0));
  *last = static_cast<int>(std::clamp(std::ceil(t1) + 1.0, lo - 1.0, hi));
}

}  // namespace

float LogOddsCanvas::Sum(int i, int j) const {
  const int x = i - min_cell_.x(), y = j - min_cell_.y();
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;
  return sums_[static_cast<size_t>(y) * width_ + x];
}

bool LogOddsCanvas::ObservedAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d cell = (point / resolution_).array().floor();
  return std::abs(Sum(static_cast<int>(cell.x()), static_cast<int>(cell.y()))) >= kZero;
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

std::optional<Box2d> KnownBox(const OccupancyGrid& grid) {
  CellIndex lo, hi;
  if (!grid.KnownBounds(&lo, &hi)) return std::nullopt;
  const double r = grid.resolution();
  return Box2d{grid.origin() + r * lo.cast<double>().matrix(),
               grid.origin() + r * (hi + 1).cast<double>().matrix()};
}

Box2d PlaceBox(const Box2d& box, const Rigid2d& box_to_frame) {
  const Eigen::Vector2d& a = box.min;
  const Eigen::Vector2d& b = box.max;
  Box2d placed{Eigen::Vector2d::Constant(1e300), Eigen::Vector2d::Constant(-1e300)};
  for (const Eigen::Vector2d& corner :
       {a, b, Eigen::Vector2d(a.x(), b.y()), Eigen::Vector2d(b.x(), a.y())}) {
    const Eigen::Vector2d p = box_to_frame * corner;
    placed.min = placed.min.cwiseMin(p);
    placed.max = placed.max.cwiseMax(p);
  }
  return placed;
}

std::optional<Box2d> PlacedBounds(const OccupancyGrid& submap, const Rigid2d& submap_to_frame) {
  const std::optional<Box2d> box = KnownBox(submap);
  if (!box) return std::nullopt;
  return PlaceBox(*box, submap_to_frame);
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
  // A canvas point (i + u, j + v) * resolution lands on submap cell floor(q), with
  // q = step * (i + u, j + v) + offset: linear in i, so each row is a start and a stride.
  const Rigid2d frame_to_submap = submap_to_frame.inverse();
  const double inv_res = 1.0 / submap.resolution();
  const Eigen::Matrix2d step = frame_to_submap.rotation_matrix() * (resolution_ * inv_res);
  const Eigen::Vector2d offset = (frame_to_submap.translation() - submap.origin()) * inv_res;
  const std::vector<float>& cells = submap.log_odds();
  const int w = submap.width(), h = submap.height();
  std::vector<Eigen::Vector2d> starts(static_cast<size_t>(samples) * samples);
  for (int j = lo.y(); j <= hi.y(); ++j) {
    // Each sample's submap coordinates at i = lo.x(), and the canvas cells of this row that
    // can reach the submap at all.
    int first = 0, last = hi.x() - lo.x();
    int row_first = last + 1, row_last = -1;
    for (int sy = 0; sy < samples; ++sy) {
      for (int sx = 0; sx < samples; ++sx) {
        const Eigen::Vector2d& q0 = starts[static_cast<size_t>(sy) * samples + sx] =
            step * Eigen::Vector2d(lo.x() + (sx + 0.5) / samples, j + (sy + 0.5) / samples) +
            offset;
        int a = first, b = last;
        ClipLine(q0.x(), step(0, 0), w, &a, &b);
        ClipLine(q0.y(), step(1, 0), h, &a, &b);
        if (a <= b) {
          row_first = std::min(row_first, a);
          row_last = std::max(row_last, b);
        }
      }
    }
    float* row = &sums_[static_cast<size_t>(j - min_cell_.y()) * width_ + (lo.x() - min_cell_.x())];
    for (int t = row_first; t <= row_last; ++t) {
      float most = 0.0f, least = 0.0f;
      for (const Eigen::Vector2d& q0 : starts) {
        const double qx = q0.x() + step(0, 0) * t, qy = q0.y() + step(1, 0) * t;
        const int cx = static_cast<int>(std::floor(qx)), cy = static_cast<int>(std::floor(qy));
        if (cx < 0 || cy < 0 || cx >= w || cy >= h) continue;
        const float v = cells[static_cast<size_t>(cy) * w + cx];
        most = std::max(most, v);
        least = std::min(least, v);
      }
      const float value = most > 0.0f ? most : least;
      if (value != 0.0f) row[t] += weight * value;
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
