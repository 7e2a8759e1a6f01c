#include "robot_agent/slam/particle_submaps.h"

#include <algorithm>
#include <utility>

namespace fleetmap {
namespace {

// Poses that moved less than this are not worth re-publishing a submap for.
constexpr double kMinTranslationChange = 1e-3;
constexpr double kMinRotationChange = 1e-4;

bool SamePoses(const std::vector<Rigid2d>& a, const std::vector<Rigid2d>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if ((a[i].translation() - b[i].translation()).norm() > kMinTranslationChange ||
        std::abs(NormalizeAngle(a[i].rotation() - b[i].rotation())) > kMinRotationChange) {
      return false;
    }
  }
  return true;
}

}  // namespace

ParticleSubmaps::ParticleSubmaps(std::string robot_id, int keyframes_per_submap,
                                 const OccupancyGridOptions& grid)
    : robot_id_(std::move(robot_id)), per_submap_(std::max(1, keyframes_per_submap)), grid_options_(grid) {}

void ParticleSubmaps::AddKeyframe(const LaserScan& scan) {
  scans_.push_back(scan);
  dirty_ = true;
}

void ParticleSubmaps::SetPoses(const std::vector<Rigid2d>& keyframe_poses) {
  poses_ = keyframe_poses;
  dirty_ = true;
}

void ParticleSubmaps::Finish() {
  finishing_ = true;
  dirty_ = true;
}

Submap ParticleSubmaps::Render(size_t group, bool finished) const {
  Submap submap;
  submap.robot_id = robot_id_;
  submap.submap_id = static_cast<int64_t>(group);
  submap.finished = finished;
  submap.grid = OccupancyGrid(grid_options_);
  const size_t begin = group * static_cast<size_t>(per_submap_);
  const size_t end = std::min({scans_.size(), poses_.size(), begin + static_cast<size_t>(per_submap_)});
  if (begin >= end) return submap;
  // Anchored at the first pose's position with the map's axes, like the scan-matching backend.
  submap.submap_in_local = Rigid2d(poses_[begin].translation(), 0.0);
  const Rigid2d local_to_submap = submap.submap_in_local.inverse();
  for (size_t i = begin; i < end; ++i) {
    submap.grid.InsertScan(scans_[i], local_to_submap * poses_[i]);
    submap.scan_poses.push_back({scans_[i].timestamp, poses_[i]});
  }
  return submap;
}

std::optional<Submap> ParticleSubmaps::RenderPublished(int64_t submap_id) const {
  if (submap_id < 0 || static_cast<size_t>(submap_id) >= groups_.size()) return std::nullopt;
  const Group& group = groups_[static_cast<size_t>(submap_id)];
  if (group.revision < 0) return std::nullopt;
  Submap submap = Render(static_cast<size_t>(submap_id), group.published_finished);
  submap.revision = group.revision;
  return submap;
}

std::vector<Submap> ParticleSubmaps::TakeUpdates(size_t max_count) {
  std::vector<Submap> updates;
  if (!dirty_) return updates;
  dirty_ = false;
  const size_t count = std::min(scans_.size(), poses_.size());
  const size_t per = static_cast<size_t>(per_submap_);
  const size_t group_count = (count + per - 1) / per;
  if (groups_.size() < group_count) groups_.resize(group_count);
  for (size_t g = 0; g < group_count; ++g) {
    if (updates.size() >= max_count) {
      dirty_ = true;  // the rest on the next call
      break;
    }
    const size_t begin = g * per, end = std::min(count, begin + per);
    const bool finished = end - begin == per || finishing_;
    const std::vector<Rigid2d> poses(poses_.begin() + static_cast<long>(begin), poses_.begin() + static_cast<long>(end));
    Group& group = groups_[g];
    if (group.revision >= 0 && group.published_finished == finished && SamePoses(poses, group.published_poses)) {
      continue;
    }
    Submap submap = Render(g, finished);
    submap.revision = ++group.revision;
    group.published_poses = poses;
    group.published_finished = finished;
    updates.push_back(std::move(submap));
  }
  return updates;
}

}  // namespace fleetmap
