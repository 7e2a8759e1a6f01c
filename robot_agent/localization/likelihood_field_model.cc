#include "robot_agent/localization/likelihood_field_model.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

float BeamLogLikelihood(double distance, const LikelihoodFieldModelOptions& options) {
  const double sigma = std::max(options.sigma_hit, 1e-3);
  const double gauss = std::exp(-0.5 * distance * distance / (sigma * sigma)) /
                       (sigma * std::sqrt(2.0 * M_PI));
  const double uniform = 1.0 / std::max(options.max_range, 1e-3);
  return static_cast<float>(std::log(options.z_hit * gauss + options.z_rand * uniform));
}

}  // namespace

LikelihoodFieldModel::LikelihoodFieldModel(const LikelihoodField& field,
                                           const LikelihoodFieldModelOptions& options)
    : options_(options),
      origin_x_(static_cast<float>(field.origin().x())),
      origin_y_(static_cast<float>(field.origin().y())),
      inverse_resolution_(static_cast<float>(1.0 / field.resolution())),
      width_(field.width()),
      height_(field.height()) {
  outside_log_likelihood_ = BeamLogLikelihood(field.max_distance(), options_);
  cell_log_likelihood_.resize(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      cell_log_likelihood_[static_cast<size_t>(y) * width_ + x] =
          field.has_obstacles() ? BeamLogLikelihood(field.CellDistance(x, y), options_)
                                : outside_log_likelihood_;
    }
  }
  beam_points_.reserve(static_cast<size_t>(std::max(options_.max_beams, 1)));
}

float LikelihoodFieldModel::PointLogLikelihood(float x, float y) const {
  const int cx = static_cast<int>(std::floor((x - origin_x_) * inverse_resolution_));
  const int cy = static_cast<int>(std::floor((y - origin_y_) * inverse_resolution_));
  if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) return outside_log_likelihood_;
  return cell_log_likelihood_[static_cast<size_t>(cy) * width_ + cx];
}

void LikelihoodFieldModel::SelectBeams(const LaserScan& scan) {
  beam_points_.clear();
  const int returns = scan.CountReturns();
  if (returns == 0 || options_.max_beams <= 0) return;
  const int wanted = std::min(options_.max_beams, returns);
  // Take every `step`-th valid return (fractional step spreads them over the whole field of view).
  const double step = static_cast<double>(returns) / wanted;
  double next = 0.5 * step;
  int valid_index = 0;
  for (int i = 0; i < scan.size() && static_cast<int>(beam_points_.size()) < wanted; ++i) {
    if (!scan.IsReturn(i)) continue;
    if (valid_index >= static_cast<int>(next)) {
      const float r = scan.ranges[static_cast<size_t>(i)];
      const Eigen::Vector2f in_sensor(r * std::cos(scan.angle(i)), r * std::sin(scan.angle(i)));
      beam_points_.push_back(scan.sensor_in_robot * in_sensor);
      next += step;
    }
    ++valid_index;
  }
}

int LikelihoodFieldModel::ComputeLogLikelihoods(const LaserScan& scan,
                                                const std::vector<Particle>& particles,
                                                std::vector<double>* log_likelihoods) {
  SelectBeams(scan);
  log_likelihoods->assign(particles.size(), 0.0);
  if (beam_points_.empty()) return 0;
  const float* table = cell_log_likelihood_.data();
  const int beams = static_cast<int>(beam_points_.size());
  for (size_t p = 0; p < particles.size(); ++p) {
    const Rigid2d& pose = particles[p].robot_in_map;
    // Map coordinates pre-scaled to cells: end = (R * b + t - origin) / resolution.
    const float c = static_cast<float>(std::cos(pose.rotation())) * inverse_resolution_;
    const float s = static_cast<float>(std::sin(pose.rotation())) * inverse_resolution_;
    const float tx = (static_cast<float>(pose.x()) - origin_x_) * inverse_resolution_;
    const float ty = (static_cast<float>(pose.y()) - origin_y_) * inverse_resolution_;
    float sum = 0.0f;
    for (int b = 0; b < beams; ++b) {
      const Eigen::Vector2f& point = beam_points_[static_cast<size_t>(b)];
      const float fx = c * point.x() - s * point.y() + tx;
      const float fy = s * point.x() + c * point.y() + ty;
      // Casting a negative value truncates toward zero; the >= 0 test on the float avoids that.
      if (fx >= 0.0f && fy >= 0.0f) {
        const int cx = static_cast<int>(fx);
        const int cy = static_cast<int>(fy);
        if (cx < width_ && cy < height_) {
          sum += table[static_cast<size_t>(cy) * width_ + cx];
          continue;
        }
      }
      sum += outside_log_likelihood_;
    }
    (*log_likelihoods)[p] = options_.log_likelihood_scale * static_cast<double>(sum);
  }
  return beams;
}

}  // namespace fleetmap
