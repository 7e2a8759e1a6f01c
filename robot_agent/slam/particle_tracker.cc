#include "robot_agent/slam/particle_tracker.h"

#include <utility>

#include "robot_agent/slam/degeneracy.h"

namespace fleetmap {

ScanMatcherOptions ParticleTrackerOptions::DefaultMatcherOptions() {
  ScanMatcherOptions options;
  options.search.linear_window = 0.2;
  options.search.angular_window = 0.12;
  options.search.angular_step = 0.01;
  options.refinement.prior_translation_sigma = 0.2;
  options.refinement.prior_rotation_sigma = 0.1;
  options.min_score = 0.35;
  return options;
}

MatchGridOptions ParticleTrackerOptions::DefaultGrid() {
  MatchGridOptions options;
  options.join_scan_returns = false;
  return options;
}

ParticleTracker::ParticleTracker(const ParticleTrackerOptions& options)
    : options_(options), target_(options.grid) {}

void ParticleTracker::AddKeyframe(std::vector<Eigen::Vector2f> points) {
  recent_.push_back(std::move(points));
  ++keyframe_count_;
  while (static_cast<int>(recent_.size()) > std::max(1, options_.keyframes)) recent_.pop_front();
}

void ParticleTracker::Rebuild(const std::vector<Rigid2d>& keyframe_poses) {
  target_ = MatchGrid(options_.grid);
  if (keyframe_poses.size() != keyframe_count_) return;
  const size_t first = keyframe_count_ - recent_.size();
  for (size_t i = 0; i < recent_.size(); ++i) target_.AddPoints(recent_[i], keyframe_poses[first + i]);
}

std::optional<Rigid2d> ParticleTracker::Track(const std::vector<Eigen::Vector2f>& points,
                                              const Rigid2d& predicted,
                                              const Eigen::Matrix2d& normal_scatter) const {
  if (points.empty() || target_.empty()) return std::nullopt;
  ScanMatcherOptions options = options_.matcher;
  options.use_correlative_search = false;
  std::optional<ScanMatchResult> match = MatchScan(points, target_, nullptr, predicted, predicted, options);
  if (!match || match->score < options_.search_below_score) {
    options.use_correlative_search = true;
    std::optional<ScanMatchResult> searched = MatchScan(points, target_, nullptr, predicted, predicted, options);
    if (searched && (!match || searched->score > match->score)) match = searched;
  }
  if (!match) return std::nullopt;
  if (options_.min_observed_normals <= 0.0) return match->pose;
  return KeepObservedDirections(predicted, match->pose, normal_scatter,
                                options_.min_observed_normals);
}

}  // namespace fleetmap
