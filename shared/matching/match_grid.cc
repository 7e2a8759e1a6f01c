#include "shared/matching/match_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace fleetmap {
namespace {

// Grids grow in whole blocks so a robot driving along an edge does not reallocate per scan.
constexpr int kGrowthBlock = 64;
// A grid this large (1 GiB of distances) means corrupt poses, not a real map; refuse to grow.
constexpr double kMaxCells = 1 << 28;

int FloorToBlock(int v) {
  return static_cast<int>(std::floor(static_cast<double>(v) / kGrowthBlock)) * kGrowthBlock;
}

}  // namespace

MatchGrid::MatchGrid(const MatchGridOptions& options)
    : options_(options),
      max_squared_(static_cast<float>(options.max_distance * options.max_distance)) {
  if (options_.observed_block < 1 || kGrowthBlock % options_.observed_block != 0)
    options_.observed_block = 1;
  while ((1 << observed_shift_) < options_.observed_block) ++observed_shift_;
}

MatchGrid MatchGrid::FromLikelihoodField(const LikelihoodField& field, double max_distance) {
  MatchGridOptions options;
  options.resolution = field.resolution();
  options.max_distance = max_distance;
  MatchGrid grid(options);
  grid.origin_ = field.origin();
  grid.width_ = field.width();
  grid.height_ = field.height();
  const size_t n = static_cast<size_t>(grid.width_) * static_cast<size_t>(grid.height_);
  grid.squared_.resize(n);
  grid.has_point_.assign(n, 0);
  const float limit = static_cast<float>(max_distance);
  for (int y = 0; y < grid.height_; ++y) {
    for (int x = 0; x < grid.width_; ++x) {
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(grid.width_) + static_cast<size_t>(x);
      const float d = std::min(limit, field.CellDistance(x, y));
      grid.squared_[i] = d * d;
      if (d == 0.0f && field.has_obstacles()) {
        grid.has_point_[i] = 1;
        ++grid.obstacle_count_;
      }
    }
  }
  return grid;
}

MatchGrid MatchGrid::FromOccupancyGrid(const OccupancyGrid& occupancy, float occupied_probability,
                                       const MatchGridOptions& options) {
  std::vector<Eigen::Vector2d> points;
  const float threshold = ProbabilityToLogOdds(occupied_probability);
  const std::vector<float>& cells = occupancy.log_odds();
  for (int y = 0; y < occupancy.height(); ++y) {
    for (int x = 0; x < occupancy.width(); ++x) {
      if (cells[static_cast<size_t>(y) * static_cast<size_t>(occupancy.width()) + static_cast<size_t>(x)] > threshold) {
        points.push_back(occupancy.CellCenter(CellIndex(x, y)));
      }
    }
  }
  return FromPoints(points, options);
}

MatchGrid MatchGrid::FromPoints(const std::vector<Eigen::Vector2d>& points,
                                const MatchGridOptions& options) {
  MatchGrid grid(options);
  std::vector<Eigen::Vector2d> finite;
  finite.reserve(points.size());
  for (const Eigen::Vector2d& p : points) {
    if (p.allFinite()) finite.push_back(p);
  }
  grid.Add(grid.Prepare(std::move(finite), nullptr));
  return grid;
}

void MatchGrid::AddPoint(const Eigen::Vector2d& point) {
  if (!point.allFinite()) return;
  GrowToInclude(point, point);
  SurfaceElement element;
  element.centre = point;
  Stamp(element);
}

namespace {

std::vector<Eigen::Vector2d> ToMap(const std::vector<Eigen::Vector2f>& points_in_frame,
                                   const Rigid2d& frame_in_map) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(points_in_frame.size());
  for (const Eigen::Vector2f& p : points_in_frame) {
    const Eigen::Vector2d q = frame_in_map * Eigen::Vector2d(p.cast<double>());
    if (q.allFinite()) points.push_back(q);
  }
  return points;
}

}  // namespace

void MatchGrid::AddPoints(const std::vector<Eigen::Vector2f>& points_in_frame,
                          const Rigid2d& frame_in_map) {
  AddPoints(points_in_frame, {}, frame_in_map);
}

void MatchGrid::AddPoints(const std::vector<Eigen::Vector2f>& points_in_frame,
                          const std::vector<Eigen::Vector2f>& free_ends_in_frame,
                          const Rigid2d& frame_in_map) {
  Add(PrepareScan(points_in_frame, free_ends_in_frame, frame_in_map));
}

MatchGridBatch MatchGrid::PrepareScan(const std::vector<Eigen::Vector2f>& points_in_frame,
                                      const std::vector<Eigen::Vector2f>& free_ends_in_frame,
                                      const Rigid2d& frame_in_map) const {
  const Eigen::Vector2d origin = frame_in_map.translation();
  return Prepare(ToMap(points_in_frame, frame_in_map), &origin,
                 ToMap(free_ends_in_frame, frame_in_map));
}

MatchGridBatch MatchGrid::Prepare(std::vector<Eigen::Vector2d> points,
                                  const Eigen::Vector2d* origin,
                                  std::vector<Eigen::Vector2d> free_ends) const {
  MatchGridBatch batch;
  batch.has_origin = origin != nullptr && origin->allFinite();
  if (batch.has_origin) batch.origin = *origin;
  batch.elements = FitSurfaceElements(points, options_.resolution, options_.surface);
  if (batch.has_origin && options_.join_scan_returns) {
    for (const SurfaceElement& segment :
         JoinConsecutiveReturns(points, *origin, options_.scan_segments)) {
      batch.elements.push_back(segment);
    }
  }
  batch.points = std::move(points);
  batch.free_ends = std::move(free_ends);
  return batch;
}

void MatchGrid::Add(const MatchGridBatch& batch) {
  const bool trace = options_.track_observed && batch.has_origin;
  if (batch.points.empty() && (!trace || batch.free_ends.empty())) return;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = Eigen::Vector2d::Constant(-INFINITY);
  auto include = [&](const Eigen::Vector2d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const Eigen::Vector2d& p : batch.points) include(p);
  if (trace) {
    include(batch.origin);
    for (const Eigen::Vector2d& p : batch.free_ends) include(p);
  }
  // Wall pieces reach a little past their points.
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(options_.surface.max_extent);
  GrowToInclude(lo - reach, hi + reach);
  for (const SurfaceElement& element : batch.elements) Stamp(element);
  if (trace) {
    for (const Eigen::Vector2d& p : batch.points) MarkRay(batch.origin, p);
    for (const Eigen::Vector2d& p : batch.free_ends) MarkRay(batch.origin, p);
  }
}

void MatchGrid::MarkRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  // Every block the segment crosses, in order (Amanatides-Woo), the point's block included.
  const int block = options_.observed_block;
  const double block_size = options_.resolution * block;
  const Eigen::Vector2d a = (from - origin_) / block_size, b = (to - origin_) / block_size;
  const Eigen::Vector2d d = b - a;
  int x = static_cast<int>(std::floor(a.x())), y = static_cast<int>(std::floor(a.y()));
  const int end_x = static_cast<int>(std::floor(b.x())), end_y = static_cast<int>(std::floor(b.y()));
  const int step_x = d.x() > 0.0 ? 1 : -1, step_y = d.y() > 0.0 ? 1 : -1;
  const double inf = std::numeric_limits<double>::infinity();
  const double delta_x = d.x() != 0.0 ? std::abs(1.0 / d.x()) : inf;
  const double delta_y = d.y() != 0.0 ? std::abs(1.0 / d.y()) : inf;
  double next_x = d.x() != 0.0 ? ((step_x > 0 ? x + 1.0 : x) - a.x()) / d.x() : inf;
  double next_y = d.y() != 0.0 ? ((step_y > 0 ? y + 1.0 : y) - a.y()) / d.y() : inf;
  const int cells = std::abs(end_x - x) + std::abs(end_y - y);
  const int blocks_x = width_ / block, blocks_y = height_ / block;
  for (int i = 0; i <= cells; ++i) {
    if (x >= 0 && y >= 0 && x < blocks_x && y < blocks_y) {
      observed_[static_cast<size_t>(y) * static_cast<size_t>(blocks_x) + static_cast<size_t>(x)] =
          1;
    }
    if (next_x < next_y) {
      next_x += delta_x;
      x += step_x;
    } else {
      next_y += delta_y;
      y += step_y;
    }
  }
}

bool MatchGrid::SeenFree(const Eigen::Vector2d& point, double clearance) const {
  if (!options_.track_observed) return false;
  const int block = options_.observed_block;
  const Eigen::Vector2d g = (point - origin_) / options_.resolution;
  if (!(g.x() >= block && g.y() >= block && g.x() < width_ - block && g.y() < height_ - block))
    return false;
  const int x = static_cast<int>(g.x()), y = static_cast<int>(g.y());
  // The point's block and the 8 around it (any cell of a block stands for it).
  for (int dy = -block; dy <= block; dy += block) {
    for (int dx = -block; dx <= block; dx += block) {
      if (!CellObserved(x + dx, y + dy)) return false;
    }
  }
  return CellSquaredDistance(x, y) > clearance * clearance;
}

bool MatchGrid::Observed(const Eigen::Vector2d& point) const {
  if (!options_.track_observed) return true;
  const Eigen::Vector2d g = (point - origin_) / options_.resolution;
  if (!(g.x() >= 0.0 && g.y() >= 0.0 && g.x() < width_ && g.y() < height_)) return false;
  return CellObserved(static_cast<int>(g.x()), static_cast<int>(g.y()));
}

float MatchGrid::CellScore(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return 0.0f;  // as the pyramid reads it
  const float score = SquaredDistanceScore(CellSquaredDistance(x, y), max_squared_);
  return CellObserved(x, y) ? score : std::max(score, options_.unknown_score);
}

void MatchGrid::GrowToInclude(const Eigen::Vector2d& min_point, const Eigen::Vector2d& max_point) {
  // Keep a margin of max_distance so that every stamp lies fully inside the grid.
  const double r = options_.resolution;
  const int margin = static_cast<int>(std::ceil(options_.max_distance / r)) + 1;
  const Eigen::Vector2d extent = (max_point - min_point) / r;
  if (!extent.allFinite() || (extent.x() + 2 * margin) * (extent.y() + 2 * margin) > kMaxCells ||
      ((min_point - origin_).cwiseAbs().maxCoeff() / r > 1e8) ||
      ((max_point - origin_).cwiseAbs().maxCoeff() / r > 1e8)) {
    return;
  }
  auto cell_of = [&](const Eigen::Vector2d& p) {
    return Eigen::Array2i(static_cast<int>(std::floor((p.x() - origin_.x()) / r)),
                          static_cast<int>(std::floor((p.y() - origin_.y()) / r)));
  };
  Eigen::Array2i lo = cell_of(min_point) - margin;
  Eigen::Array2i hi = cell_of(max_point) + margin + 1;  // exclusive
  if (width_ > 0 && lo.x() >= 0 && lo.y() >= 0 && hi.x() <= width_ && hi.y() <= height_) return;
  if (width_ > 0) {
    lo = lo.min(Eigen::Array2i(0, 0));
    hi = hi.max(Eigen::Array2i(width_, height_));
  }
  lo = Eigen::Array2i(FloorToBlock(lo.x()), FloorToBlock(lo.y()));
  hi = Eigen::Array2i(FloorToBlock(hi.x() + kGrowthBlock - 1), FloorToBlock(hi.y() + kGrowthBlock - 1));
  const int new_width = hi.x() - lo.x();
  const int new_height = hi.y() - lo.y();
  if (static_cast<double>(new_width) * new_height > kMaxCells) return;
  const size_t n = static_cast<size_t>(new_width) * static_cast<size_t>(new_height);
  std::vector<float> squared(n, max_squared_);
  std::vector<uint8_t> has_point(n, 0);
  for (int y = 0; y < height_; ++y) {
    const size_t src = static_cast<size_t>(y) * static_cast<size_t>(width_);
    const size_t dst = static_cast<size_t>(y - lo.y()) * static_cast<size_t>(new_width) +
                       static_cast<size_t>(-lo.x());
    std::copy_n(squared_.begin() + static_cast<long>(src), width_, squared.begin() + static_cast<long>(dst));
    std::copy_n(has_point_.begin() + static_cast<long>(src), width_, has_point.begin() + static_cast<long>(dst));
  }
  // Seen space in blocks; lo is a multiple of the growth block, so of the block too.
  const int block = options_.observed_block;
  const int blocks_x = width_ / block, new_blocks_x = new_width / block;
  std::vector<uint8_t> observed(
      options_.track_observed
          ? static_cast<size_t>(new_blocks_x) * static_cast<size_t>(new_height / block)
          : 0,
      0);
  for (int y = 0; options_.track_observed && y < height_ / block; ++y) {
    const size_t src = static_cast<size_t>(y) * static_cast<size_t>(blocks_x);
    const size_t dst = static_cast<size_t>(y - lo.y() / block) * static_cast<size_t>(new_blocks_x) +
                       static_cast<size_t>(-lo.x() / block);
    std::copy_n(observed_.begin() + static_cast<long>(src), blocks_x,
                observed.begin() + static_cast<long>(dst));
  }
  origin_ += r * lo.cast<double>().matrix();
  width_ = new_width;
  height_ = new_height;
  squared_ = std::move(squared);
  has_point_ = std::move(has_point);
  observed_ = std::move(observed);
}

void MatchGrid::Stamp(const SurfaceElement& element) {
  const double r = options_.resolution;
  const double gx = (element.centre.x() - origin_.x()) / r;
  const double gy = (element.centre.y() - origin_.y()) / r;
  if (!(gx >= 0.0 && gy >= 0.0 && gx < width_ && gy < height_)) return;  // not after growing
  const int cx = static_cast<int>(gx);
  const int cy = static_cast<int>(gy);
  uint8_t& seen = has_point_[static_cast<size_t>(cy) * static_cast<size_t>(width_) + static_cast<size_t>(cx)];
  if (seen) return;
  seen = 1;
  ++obstacle_count_;
  // The segment's ends, in grid units; cells within max_distance of it are updated. Add
  // grew the grid to hold every element (wall pieces reach at most max_extent past their point,
  // joined segments lie between two points of the batch); the box is clipped all the same.
  const Eigen::Vector2d centre(gx, gy);
  const Eigen::Vector2d tangent = element.tangent;
  const double reach_minus = element.extent_minus / r, reach_plus = element.extent_plus / r;
  const Eigen::Vector2d a = centre - reach_minus * tangent, b = centre + reach_plus * tangent;
  const double radius = options_.max_distance / r;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min(a.x(), b.x()) - radius)));
  const int x1 = std::min(width_ - 1, static_cast<int>(std::ceil(std::max(a.x(), b.x()) + radius)));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min(a.y(), b.y()) - radius)));
  const int y1 = std::min(height_ - 1, static_cast<int>(std::ceil(std::max(a.y(), b.y()) + radius)));
  const double r2 = r * r;
  for (int y = y0; y <= y1; ++y) {
    float* row = squared_.data() + static_cast<size_t>(y) * static_cast<size_t>(width_);
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d d(x + 0.5 - gx, y + 0.5 - gy);
      const double s = std::clamp(tangent.dot(d), -reach_minus, reach_plus);
      const float d2 = static_cast<float>((d - s * tangent).squaredNorm() * r2);
      if (d2 < row[x]) row[x] = d2;
    }
  }
}

namespace {

// Catmull-Rom weights for the four samples around t in [0, 1), with first and second derivatives.
// Catmull-Rom reproduces quadratics exactly, which is why the grid stores squared distances.
void CubicWeights(double t, double w[4], double dw[4], double ddw[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
  dw[0] = 0.5 * (-3.0 * t2 + 4.0 * t - 1.0);
  dw[1] = 0.5 * (9.0 * t2 - 10.0 * t);
  dw[2] = 0.5 * (-9.0 * t2 + 8.0 * t + 1.0);
  dw[3] = 0.5 * (3.0 * t2 - 2.0 * t);
  ddw[0] = -3.0 * t + 2.0;
  ddw[1] = 9.0 * t - 5.0;
  ddw[2] = -9.0 * t + 4.0;
  ddw[3] = 3.0 * t - 1.0;
}

}  // namespace

double MatchGrid::SquaredDistance(const Eigen::Vector2d& point, Eigen::Vector2d* gradient,
                                  Eigen::Matrix2d* hessian) const {
  // Cell centres are at half-integer grid coordinates.
  const double r = options_.resolution;
  const double gx = (point.x() - origin_.x()) / r - 0.5;
  const double gy = (point.y() - origin_.y()) / r - 0.5;
  // Written so that NaN and huge coordinates fail the test before any integer conversion.
  if (!(gx >= 1.0 && gy >= 1.0 && gx < width_ - 2 && gy < height_ - 2)) {
    if (gradient != nullptr) gradient->setZero();
    if (hessian != nullptr) hessian->setZero();
    return max_squared_;
  }
  const double fx = std::floor(gx), fy = std::floor(gy);
  const int x0 = static_cast<int>(fx) - 1, y0 = static_cast<int>(fy) - 1;
  double wx[4], dwx[4], ddwx[4], wy[4], dwy[4], ddwy[4];
  CubicWeights(gx - fx, wx, dwx, ddwx);
  CubicWeights(gy - fy, wy, dwy, ddwy);
  double value = 0.0, dx = 0.0, dy = 0.0, dxx = 0.0, dxy = 0.0, dyy = 0.0;
  for (int j = 0; j < 4; ++j) {
    const float* row = squared_.data() + static_cast<size_t>(y0 + j) * static_cast<size_t>(width_) +
                       static_cast<size_t>(x0);
    const double v = wx[0] * row[0] + wx[1] * row[1] + wx[2] * row[2] + wx[3] * row[3];
    const double vx = dwx[0] * row[0] + dwx[1] * row[1] + dwx[2] * row[2] + dwx[3] * row[3];
    const double vxx = ddwx[0] * row[0] + ddwx[1] * row[1] + ddwx[2] * row[2] + ddwx[3] * row[3];
    value += wy[j] * v;
    dx += wy[j] * vx;
    dy += dwy[j] * v;
    dxx += wy[j] * vxx;
    dxy += dwy[j] * vx;
    dyy += ddwy[j] * v;
  }
  if (gradient != nullptr) *gradient = Eigen::Vector2d(dx, dy) / r;
  if (hessian != nullptr) *hessian << dxx / (r * r), dxy / (r * r), dxy / (r * r), dyy / (r * r);
  return value;
}

double MatchGrid::Distance(const Eigen::Vector2d& point) const {
  return std::sqrt(std::max(0.0, SquaredDistance(point)));
}

}  // namespace fleetmap
