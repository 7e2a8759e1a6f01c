#include "shared/eval/absolute_trajectory_error.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "shared/eval/rigid_alignment.h"

namespace fleetmap {
namespace {

struct Pair {
  Rigid2d estimate;
  Rigid2d ground_truth;
};

std::vector<Pair> Associate(const Trajectory& estimate, const Trajectory& ground_truth,
                            double max_time_difference, int* unmatched) {
  Trajectory sorted = ground_truth;
  std::stable_sort(sorted.begin(), sorted.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.timestamp < b.timestamp;
  });
  std::vector<Pair> pairs;
  *unmatched = 0;
  for (const StampedPose& pose : estimate) {
    const auto it =
        std::lower_bound(sorted.begin(), sorted.end(), pose.timestamp,
                         [](const StampedPose& p, double t) { return p.timestamp < t; });
    const StampedPose* best = it != sorted.end() ? &*it : nullptr;
    if (it != sorted.begin() && (best == nullptr || pose.timestamp - (it - 1)->timestamp <
                                                        best->timestamp - pose.timestamp)) {
      best = &*(it - 1);
    }
    if (best == nullptr || std::abs(best->timestamp - pose.timestamp) > max_time_difference) {
      ++*unmatched;
      continue;
    }
    pairs.push_back(Pair{pose.pose, best->pose});
  }
  return pairs;
}

}  // namespace

std::optional<AteResult> EvaluateAte(const Trajectory& estimate, const Trajectory& ground_truth,
                                     const AteOptions& options) {
  AteResult result;
  const std::vector<Pair> pairs =
      Associate(estimate, ground_truth, options.max_time_difference, &result.unmatched);
  if (pairs.empty() || (options.align && pairs.size() < 2)) return std::nullopt;
  if (options.align) {
    std::vector<Eigen::Vector2d> source;
    std::vector<Eigen::Vector2d> target;
    for (const Pair& pair : pairs) {
      source.push_back(pair.estimate.translation());
      target.push_back(pair.ground_truth.translation());
    }
    const std::optional<Rigid2d> alignment = AlignPoints2d(source, target);
    if (!alignment) return std::nullopt;
    result.ground_truth_from_estimate = *alignment;
  }
  std::vector<double> translation;
  double squared_translation = 0.0;
  double squared_rotation = 0.0;
  for (const Pair& pair : pairs) {
    const Rigid2d aligned = result.ground_truth_from_estimate * pair.estimate;
    const double t = (aligned.translation() - pair.ground_truth.translation()).norm();
    const double r =
        NormalizeAngle(aligned.rotation() - pair.ground_truth.rotation()) * 180.0 / M_PI;
    translation.push_back(t);
    squared_translation += t * t;
    squared_rotation += r * r;
  }
  result.matched = static_cast<int>(pairs.size());
  result.rmse_translation = std::sqrt(squared_translation / result.matched);
  result.rmse_rotation_deg = std::sqrt(squared_rotation / result.matched);
  result.translation = ComputeMeanStd(translation);
  return result;
}

}  // namespace fleetmap
