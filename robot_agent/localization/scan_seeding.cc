#include "robot_agent/localization/scan_seeding.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

ScanSeeder::ScanSeeder(const OccupancyGrid& map, const ScanSeedingOptions& options)
    : options_(options) {
  MatchGridOptions grid_options;
  grid_options.resolution = options.resolution;
  grid_options.max_distance = 3.0 * options.resolution;
  grid_ = std::make_unique<MatchGrid>(MatchGrid::FromOccupancyGrid(map, 0.6f, grid_options));
  pyramid_ = std::make_unique<MatchGridPyramid>(*grid_);
  const Eigen::Vector2d size(map.width() * map.resolution(), map.height() * map.resolution());
  centre_ = Rigid2d(map.origin() + 0.5 * size, 0.0);
  half_extent_ = 0.5 * size.maxCoeff();
}

std::vector<Eigen::Vector2f> ScanSeeder::SelectPoints(
    const std::vector<Eigen::Vector2f>& points) const {
  std::vector<Eigen::Vector2f> near;
  for (const Eigen::Vector2f& p : points) {
    if (p.norm() <= options_.max_range) near.push_back(p);
  }
  if (static_cast<int>(near.size()) <= options_.max_points) return near;
  std::vector<Eigen::Vector2f> taken;
  const double step = static_cast<double>(near.size()) / options_.max_points;
  for (int i = 0; i < options_.max_points; ++i) {
    taken.push_back(near[static_cast<size_t>(i * step)]);
  }
  return taken;
}

std::optional<CorrelativeMatch> ScanSeeder::Search(
    const std::vector<Eigen::Vector2f>& points) const {
  const std::vector<Eigen::Vector2f> selected = SelectPoints(points);
  if (selected.size() < 10) return std::nullopt;
  CorrelativeSearchOptions search;
  search.linear_window = half_extent_;
  search.angular_window = M_PI;
  search.min_score = options_.min_score;
  std::optional<CorrelativeMatch> match =
      SearchBranchAndBound(selected, *pyramid_, centre_, search);
  if (!match || match->score < options_.min_score) return std::nullopt;
  return match;
}

void ScanSeeder::Seed(const Rigid2d& pose, std::vector<Particle>* particles,
                      std::mt19937& rng) const {
  if (particles->empty()) return;
  double total = 0.0;
  for (const Particle& p : *particles) total += p.weight;
  const double mean_weight = total / static_cast<double>(particles->size());
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<size_t> pick(0, particles->size() - 1);
  const int count = static_cast<int>(options_.fraction * static_cast<double>(particles->size()));
  for (int i = 0; i < count; ++i) {
    Particle& p = (*particles)[pick(rng)];
    p.robot_in_map = Rigid2d(
        pose.translation() + options_.position_std * Eigen::Vector2d(normal(rng), normal(rng)),
        pose.rotation() + options_.heading_std * normal(rng));
    p.weight = mean_weight;
  }
}

}  // namespace fleetmap
