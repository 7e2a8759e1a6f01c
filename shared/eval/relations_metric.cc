#include "shared/eval/relations_metric.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace fleetmap {
namespace {

// Timestamp-sorted view of a trajectory for exact-time look-ups.
class PoseLookup {
 public:
  explicit PoseLookup(const Trajectory& trajectory) : poses_(trajectory) {
    std::stable_sort(poses_.begin(), poses_.end(), [](const StampedPose& a, const StampedPose& b) {
      return a.timestamp < b.timestamp;
    });
  }

  // The pose whose timestamp is nearest `timestamp`, if within `tolerance`.
  std::optional<Rigid2d> At(double timestamp, double tolerance) const {
    const auto it =
        std::lower_bound(poses_.begin(), poses_.end(), timestamp,
                         [](const StampedPose& pose, double t) { return pose.timestamp < t; });
    const StampedPose* best = nullptr;
    if (it != poses_.end()) best = &*it;
    if (it != poses_.begin()) {
      const StampedPose& before = *(it - 1);
      if (best == nullptr || timestamp - before.timestamp < best->timestamp - timestamp) {
        best = &before;
      }
    }
    if (best == nullptr || std::abs(best->timestamp - timestamp) > tolerance) return std::nullopt;
    return best->pose;
  }

 private:
  Trajectory poses_;
};

}  // namespace

Rigid2d RelationError(const Rigid2d& from_pose, const Rigid2d& to_pose, const Rigid2d& expected) {
  return (from_pose.inverse() * to_pose) * expected.inverse();
}

RelationsResult EvaluateRelations(const Trajectory& trajectory,
                                  const std::vector<Relation>& relations,
                                  const RelationsOptions& options) {
  const PoseLookup lookup(trajectory);
  std::vector<double> translation;
  std::vector<double> squared_translation;
  std::vector<double> rotation;
  std::vector<double> squared_rotation;
  RelationsResult result;
  for (const Relation& relation : relations) {
    const std::optional<Rigid2d> from =
        lookup.At(relation.from_timestamp, options.timestamp_tolerance);
    const std::optional<Rigid2d> to = lookup.At(relation.to_timestamp, options.timestamp_tolerance);
    if (!from || !to) {
      ++result.skipped;
      continue;
    }
    const Rigid2d error = RelationError(*from, *to, relation.expected);
    const double t = error.translation().norm();
    const double r = std::abs(error.rotation()) * 180.0 / M_PI;
    translation.push_back(t);
    squared_translation.push_back(t * t);
    rotation.push_back(r);
    squared_rotation.push_back(r * r);
    ++result.used;
  }
  result.translation = ComputeMeanStd(translation);
  result.squared_translation = ComputeMeanStd(squared_translation);
  result.rotation_deg = ComputeMeanStd(rotation);
  result.squared_rotation_deg = ComputeMeanStd(squared_rotation);
  return result;
}

}  // namespace fleetmap
