#include "robot_agent/slam/submap_builder.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

namespace fleetmap {

SubmapBuilder::SubmapBuilder(std::string robot_id, const SubmapOptions& options)
    : robot_id_(std::move(robot_id)), options_(options) {}

std::optional<SubmapBuilder::Insertion> SubmapBuilder::Insert(const LaserScan& scan,
                                                             const Rigid2d& robot_in_local) {
  if (!robot_in_local.IsFinite()) return std::nullopt;
  if (!active_) {
    active_ = std::make_unique<Submap>();
    active_->robot_id = robot_id_;
    active_->submap_id = next_id_++;
    // The anchor keeps the first pose's position but the map's axes, so that an unrevised
    // submap drops into the local map by a translation.
    active_->submap_in_local = Rigid2d(robot_in_local.translation(), 0.0);
    active_->grid = OccupancyGrid(options_.grid);
    active_travel_ = 0.0;
  } else if (!active_->scan_poses.empty()) {
    active_travel_ += (robot_in_local.translation() - active_->scan_poses.back().pose.translation()).norm();
  }
  active_->grid.InsertScan(scan, active_->submap_in_local.inverse() * robot_in_local);
  active_->scan_poses.push_back({scan.timestamp, robot_in_local});
  active_changed_ = true;
  const Insertion insertion{active_->submap_id, active_->submap_in_local};
  const bool enough_scans =
      options_.max_scans > 0 && static_cast<int>(active_->scan_poses.size()) >= options_.max_scans;
  const bool enough_travel = options_.max_travel > 0.0 && active_travel_ >= options_.max_travel;
  if (enough_scans || enough_travel) FinishActiveInternal();
  return insertion;
}

void SubmapBuilder::FinishActive() {
  if (active_) FinishActiveInternal();
}

void SubmapBuilder::FinishActiveInternal() {
  active_->finished = true;
  ++active_->revision;
  finished_.push_back(std::move(*active_));
  active_.reset();
  active_changed_ = false;
}

bool SubmapBuilder::Revise(int64_t submap_id, const Rigid2d& new_submap_in_local) {
  auto move = [&](Submap& submap) {
    const Rigid2d correction = new_submap_in_local * submap.submap_in_local.inverse();
    for (StampedPose& pose : submap.scan_poses) pose.pose = correction * pose.pose;
    submap.submap_in_local = new_submap_in_local;
    ++submap.revision;
  };
  if (active_ && active_->submap_id == submap_id) {
    move(*active_);
    active_changed_ = true;
    return true;
  }
  for (Submap& submap : finished_) {
    if (submap.submap_id == submap_id) {
      move(submap);
      return true;
    }
  }
  return false;
}

std::vector<Submap> SubmapBuilder::TakeUpdates(size_t max_count) {
  std::vector<Submap> updates;
  const size_t taken = std::min(max_count, finished_.size());
  updates.reserve(taken + 1);
  std::move(finished_.begin(), finished_.begin() + static_cast<long>(taken), std::back_inserter(updates));
  finished_.erase(finished_.begin(), finished_.begin() + static_cast<long>(taken));
  if (active_ && active_changed_ && updates.size() < max_count) {
    updates.push_back(*active_);
    ++active_->revision;  // the next snapshot of it differs from this one
    active_changed_ = false;
  }
  return updates;
}

}  // namespace fleetmap
