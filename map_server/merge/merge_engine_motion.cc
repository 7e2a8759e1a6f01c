// MergeEngine: the relative heading of two robots from detections of one by the other while
// the seen robot moved, independent of how their maps look.

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {
namespace {

double MaxSigma(const Eigen::Matrix2d& covariance) {
  return std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance).eigenvalues().maxCoeff());
}

}  // namespace

std::optional<MergeEngine::SeenPositions> MergeEngine::PositionsAt(const RobotDetection& d) const {
  const auto a_robot = RobotInComponent(d.observer_id, d.timestamp);
  const auto b_robot = RobotInComponent(d.observed_id, d.timestamp);
  if (!a_robot || !b_robot) return std::nullopt;
  return SeenPositions{*a_robot * d.position_in_observer, b_robot->translation()};
}

std::optional<MergeEngine::HeadingPrior> MergeEngine::HeadingFromMotion(size_t index) const {
  const RobotDetection& d = detections_[index];
  const auto now = PositionsAt(d);
  if (!now || options_.motion_heading_window <= 0.0) return std::nullopt;
  const double floor2 = options_.detection_sigma_floor * options_.detection_sigma_floor;
  // One estimate per earlier or later detection of the same robot from the same component,
  // far enough along its path: the direction it moved in the observer's frame against the
  // direction it moved in its own.
  std::vector<HeadingPrior> estimates;
  for (size_t j = 0; j < detections_.size(); ++j) {
    const RobotDetection& e = detections_[j];
    if (j == index || e.observed_id != d.observed_id || Root(e.observer_id) != Root(d.observer_id) ||
        std::abs(e.timestamp - d.timestamp) > options_.motion_heading_window) {
      continue;
    }
    const auto then = PositionsAt(e);
    if (!then) continue;
    const Eigen::Vector2d seen = now->in_observer_frame - then->in_observer_frame;
    const Eigen::Vector2d own = now->in_observed_frame - then->in_observed_frame;
    const double baseline = own.norm();
    if (baseline < options_.motion_heading_min_baseline) continue;
    const double heading = NormalizeAngle(std::atan2(seen.y(), seen.x()) - std::atan2(own.y(), own.x()));
    const double spread = std::hypot(MaxSigma(d.covariance), MaxSigma(e.covariance)) + 2.0 * std::sqrt(floor2);
    estimates.push_back(HeadingPrior{heading, spread / baseline});
  }
  // Consensus, so that one corrupted detection cannot steer the search: the estimate that the
  // most others agree with (within 3 sigma), and only when at least one other does.
  std::optional<HeadingPrior> best;
  int best_support = 0;
  for (const HeadingPrior& h : estimates) {
    int support = 0;
    for (const HeadingPrior& o : estimates) {
      support += std::abs(NormalizeAngle(o.heading - h.heading)) <= 3.0 * std::max(h.sigma, o.sigma);
    }
    if (support > best_support || (support == best_support && best && h.sigma < best->sigma)) {
      best = h;
      best_support = support;
    }
  }
  if (best_support < 2) return std::nullopt;
  return best;
}

}  // namespace fleetmap
