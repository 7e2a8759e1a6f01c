#include "shared/core/likelihood_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleetmap {
namespace {

constexpr float kInfinity = 1e20f;

// One dimension of the Felzenszwalb-Huttenlocher squared distance transform: f holds squared
// distances along a line (0 at obstacles, kInfinity elsewhere); d receives the lower envelope.
void DistanceTransform1d(const float* f, int n, float* d, std::vector<int>& v,
                         std::vector<float>& z) {
  int k = 0;
  v[0] = 0;
  z[0] = -kInfinity;
  z[1] = kInfinity;
  for (int q = 1; q < n; ++q) {
    float s;
    while (true) {
      const int p = v[static_cast<size_t>(k)];
      s = ((f[q] + static_cast<float>(q) * q) - (f[p] + static_cast<float>(p) * p)) /
          (2.0f * static_cast<float>(q - p));
      if (s > z[static_cast<size_t>(k)] || k == 0) break;
      --k;
    }
    if (s <= z[static_cast<size_t>(k)]) {
      // Only reachable for k == 0 with an infinite parabola; replace it.
      v[0] = q;
      z[0] = -kInfinity;
      z[1] = kInfinity;
      continue;
    }
    ++k;
    v[static_cast<size_t>(k)] = q;
    z[static_cast<size_t>(k)] = s;
    z[static_cast<size_t>(k) + 1] = kInfinity;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<size_t>(k) + 1] < static_cast<float>(q)) ++k;
    const int p = v[static_cast<size_t>(k)];
    const float diff = static_cast<float>(q - p);
    d[q] = diff * diff + f[p];
  }
}

}  // namespace

LikelihoodField::LikelihoodField(const OccupancyGrid& grid, const LikelihoodFieldOptions& options)
    : options_(options), resolution_(grid.resolution()) {
  const int margin = static_cast<int>(std::ceil(options.max_distance / resolution_)) + 1;
  width_ = grid.width() + 2 * margin;
  height_ = grid.height() + 2 * margin;
  origin_ = grid.origin() - Eigen::Vector2d::Constant(margin * resolution_);
  const float threshold = ProbabilityToLogOdds(options.occupied_probability);
  std::vector<uint8_t> mask(static_cast<size_t>(width_) * height_, 0);
  const std::vector<float>& cells = grid.log_odds();
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      if (cells[static_cast<size_t>(y) * grid.width() + x] > threshold) {
        mask[static_cast<size_t>(y + margin) * width_ + (x + margin)] = 1;
      }
    }
  }
  Compute(mask);
}

LikelihoodField::LikelihoodField(const std::vector<Eigen::Vector2d>& obstacles, double resolution,
                                 const LikelihoodFieldOptions& options)
    : options_(options), resolution_(resolution) {
  if (obstacles.empty()) {
    Compute({});
    return;
  }
  Eigen::Vector2d lo = obstacles.front(), hi = obstacles.front();
  for (const Eigen::Vector2d& p : obstacles) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int margin = static_cast<int>(std::ceil(options.max_distance / resolution_)) + 1;
  origin_ = (lo / resolution_).array().floor().matrix() * resolution_ -
            Eigen::Vector2d::Constant(margin * resolution_);
  width_ = static_cast<int>(std::ceil((hi.x() - origin_.x()) / resolution_)) + margin + 1;
  height_ = static_cast<int>(std::ceil((hi.y() - origin_.y()) / resolution_)) + margin + 1;
  std::vector<uint8_t> mask(static_cast<size_t>(width_) * height_, 0);
  for (const Eigen::Vector2d& p : obstacles) {
    const int x = static_cast<int>(std::floor((p.x() - origin_.x()) / resolution_));
    const int y = static_cast<int>(std::floor((p.y() - origin_.y()) / resolution_));
    mask[static_cast<size_t>(y) * width_ + x] = 1;
  }
  Compute(mask);
}

void LikelihoodField::Compute(const std::vector<uint8_t>& obstacle_mask) {
  const size_t n = static_cast<size_t>(width_) * height_;
  distance_.assign(n, static_cast<float>(options_.max_distance));
  const size_t obstacles =
      static_cast<size_t>(std::count(obstacle_mask.begin(), obstacle_mask.end(), 1));
  has_obstacles_ = obstacles > 0;
  if (!has_obstacles_) return;
  // Distances are clamped at max_distance, so only the disk of that radius round each obstacle
  // matters. Where obstacles are sparse (a few wall cells in a large grid), stamping those disks
  // is cheaper than the full transform below (measured: several times faster per cell touched),
  // and gives the same distances.
  const int reach = static_cast<int>(std::ceil(options_.max_distance / resolution_));
  const size_t disk = static_cast<size_t>((2 * reach + 1) * (2 * reach + 1));
  if (obstacles * disk < 8 * n) {
    std::vector<float> squared(n, kInfinity);
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        if (!obstacle_mask[static_cast<size_t>(y) * width_ + x]) continue;
        for (int dy = std::max(-reach, -y); dy <= std::min(reach, height_ - 1 - y); ++dy) {
          float* row = squared.data() + static_cast<size_t>(y + dy) * width_ + x;
          for (int dx = std::max(-reach, -x); dx <= std::min(reach, width_ - 1 - x); ++dx) {
            row[dx] = std::min(row[dx], static_cast<float>(dx * dx + dy * dy));
          }
        }
      }
    }
    const float max_distance = static_cast<float>(options_.max_distance);
    for (size_t i = 0; i < n; ++i) {
      distance_[i] = std::min(max_distance, std::sqrt(squared[i]) * static_cast<float>(resolution_));
    }
    return;
  }
  std::vector<float> squared(n);
  for (size_t i = 0; i < n; ++i) squared[i] = obstacle_mask[i] ? 0.0f : kInfinity;
  const int longest = std::max(width_, height_);
  std::vector<float> line_in(static_cast<size_t>(longest)), line_out(static_cast<size_t>(longest));
  std::vector<int> v(static_cast<size_t>(longest));
  std::vector<float> z(static_cast<size_t>(longest) + 1);
  for (int x = 0; x < width_; ++x) {  // columns
    for (int y = 0; y < height_; ++y) line_in[static_cast<size_t>(y)] = squared[static_cast<size_t>(y) * width_ + x];
    DistanceTransform1d(line_in.data(), height_, line_out.data(), v, z);
    for (int y = 0; y < height_; ++y) squared[static_cast<size_t>(y) * width_ + x] = line_out[static_cast<size_t>(y)];
  }
  for (int y = 0; y < height_; ++y) {  // rows
    float* row = squared.data() + static_cast<size_t>(y) * width_;
    std::copy_n(row, width_, line_in.begin());
    DistanceTransform1d(line_in.data(), width_, row, v, z);
  }
  const float max_distance = static_cast<float>(options_.max_distance);
  for (size_t i = 0; i < n; ++i) {
    distance_[i] = std::min(max_distance, std::sqrt(squared[i]) * static_cast<float>(resolution_));
  }
}

float LikelihoodField::CellDistance(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return static_cast<float>(options_.max_distance);
  return distance_[static_cast<size_t>(y) * width_ + x];
}

double LikelihoodField::Distance(const Eigen::Vector2d& point) const {
  Eigen::Vector2d unused;
  return DistanceAndGradient(point, &unused);
}

double LikelihoodField::DistanceAndGradient(const Eigen::Vector2d& point,
                                            Eigen::Vector2d* gradient) const {
  // Cell centres sit at half-integer positions; shift so that interpolation is between centres.
  const double gx = (point.x() - origin_.x()) / resolution_ - 0.5;
  const double gy = (point.y() - origin_.y()) / resolution_ - 0.5;
  const double fx = std::floor(gx), fy = std::floor(gy);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  if (x0 < 0 || y0 < 0 || x0 + 1 >= width_ || y0 + 1 >= height_) {
    gradient->setZero();
    return options_.max_distance;
  }
  const double tx = gx - fx, ty = gy - fy;
  const double d00 = CellDistance(x0, y0), d10 = CellDistance(x0 + 1, y0);
  const double d01 = CellDistance(x0, y0 + 1), d11 = CellDistance(x0 + 1, y0 + 1);
  const double bottom = d00 + tx * (d10 - d00);
  const double top = d01 + tx * (d11 - d01);
  gradient->x() = ((d10 - d00) * (1.0 - ty) + (d11 - d01) * ty) / resolution_;
  gradient->y() = (top - bottom) / resolution_;
  return bottom + ty * (top - bottom);
}

}  // namespace fleetmap
