#include "robot_agent/slam/scan_matching_slam.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "robot_agent/slam/input_order.h"
#include "robot_agent/slam/seen_surface_filter.h"
#include "shared/matching/degeneracy.h"
#include "shared/matching/point_filter.h"

namespace fleetmap {
namespace {

// `scan` without the returns flagged in `drop`, which lists the returns of
// RangeFilter(ToPointsInRobotFrame(scan), max_range) in the same order.
LaserScan WithoutReturns(const LaserScan& scan, float max_range, const std::vector<bool>& drop) {
  const std::vector<Eigen::Vector2f> returns = ToPointsInRobotFrame(scan);  // one per return beam
  LaserScan kept = scan;
  size_t r = 0, k = 0;
  for (int i = 0; i < scan.size() && r < returns.size(); ++i) {
    if (!scan.IsReturn(i)) continue;
    if (returns[r++].squaredNorm() > max_range * max_range) continue;  // not in RangeFilter's list
    if (k < drop.size() && drop[k++]) kept.ranges[static_cast<size_t>(i)] = LaserScan::kNoReturn;
  }
  return kept;
}

}  // namespace

ScanMatcherOptions ScanMatchingSlamOptions::DefaultMatcherOptions() {
  ScanMatcherOptions options;
  options.search.linear_window = 0.2;
  options.search.angular_window = 0.12;
  options.search.angular_step = 0.01;
  options.refinement.prior_translation_sigma = 0.2;
  options.refinement.prior_rotation_sigma = 0.1;
  // A narrow second pass (see PoseRefinementOptions::fine_robust_scale), a little above the
  // range noise of the lasers we map with (1-2 cm): 0.05 / 0.03 / 0.02 were measured, 0.02 best
  // on intel, aces and the simulator (docs/BENCHMARKS.md, issue 4, session 7).
  options.refinement.fine_robust_scale = 0.02;
  options.min_score = 0.35;
  return options;
}

CorrelativeSearchOptions ScanMatchingSlamOptions::NoOdometrySearchOptions() {
  CorrelativeSearchOptions options;
  options.linear_window = 0.3;
  options.angular_window = 0.3;
  options.angular_step = 0.01;
  return options;
}

ScanMatchingSlam::ScanMatchingSlam(const ScanMatchingSlamOptions& options)
    : options_(options),
      local_map_(options.local_map),
      submaps_(options.robot_id, options.submaps),
      loop_closure_(options.loop_closure) {}

bool ScanMatchingSlam::AddOdometry(const StampedPose& odometry, std::string* error) {
  if (!CheckInputTime(odometry.timestamp, last_time_, "odometry", error)) return false;
  if (!odometry_.Add(odometry, error)) return false;
  last_time_ = odometry.timestamp;
  return true;
}

bool ScanMatchingSlam::AddScan(const LaserScan& scan, std::string* error) {
  if (!CheckInputTime(scan.timestamp, last_time_, "scan", error)) return false;
  if (!scan.sensor_in_robot.IsFinite()) {
    if (error) *error = "scan with a non-finite sensor mounting pose";
    return false;
  }
  last_time_ = scan.timestamp;
  ++counters_.scans;

  const std::optional<Rigid2d> odometry = odometry_.PoseAt(scan.timestamp);
  Rigid2d predicted = current_pose_;
  if (odometry && last_odometry_) predicted = current_pose_ * (last_odometry_->inverse() * *odometry);
  if (odometry) last_odometry_ = odometry;

  std::vector<Eigen::Vector2f> points = RangeFilter(ToPointsInRobotFrame(scan), options_.max_range);
  if (points.empty()) ++counters_.no_return_scans;
  Rigid2d pose = predicted;
  // Small objects that moved since the last scan (judged at the prediction) are left out of the
  // match: another robot driving ahead faces the follower scan after scan at the same distance,
  // and in a plain corridor its back alone made the direction along it look observed, so the
  // follower stopped (east_end seeds 23 and 25: 3.2 and 3.8 m short); robots coming head-on
  // pushed the other way (robot2 0.5-0.7 m ahead on seeds 21-28).
  const LaserScan still = WithoutReturns(scan, options_.max_range, local_map_.Moved(points, predicted));
  const std::vector<Eigen::Vector2f> thinned = ReturnsInsideHorizon(
      ThinBeams(still, options_.match_beam_spacing), options_.max_range, options_.match_range_margin);
  if (!thinned.empty() && !local_map_.target().empty()) pose = Match(thinned, predicted);
  current_pose_ = pose;
  local_poses_.push_back(pose);
  trajectory_.push_back({scan.timestamp, loop_closure_.CorrectionAt(scan.timestamp) * pose});
  const std::vector<bool> mappable = local_map_.Track(points, pose);

  if (!points.empty() && ShouldInsert(pose, scan.timestamp)) {
    // Unlike the occupancy grids (where glass and dropouts make beams without a return
    // unreliable), the local map counts the space those crossed as seen: it only uses that to
    // recognise moved objects, and a cell needs its 8 neighbours crossed too, which one stray
    // beam through a wall cannot do.
    local_map_.Insert(points, mappable, NoReturnEnds(scan, options_.max_range), pose);
    last_inserted_ = StampedPose{scan.timestamp, pose};
    ++counters_.inserted;
    if (!options_.build_submaps) return true;
    LaserScan limited = scan;
    for (float& range : limited.ranges) {
      if (range > options_.max_range) range = LaserScan::kNoReturn;
    }
    const std::optional<SubmapBuilder::Insertion> insertion = submaps_.Insert(limited, pose);
    if (!insertion) return true;
    const std::vector<Eigen::Vector2f> node_points = VoxelFilter(
        ReturnsInsideHorizon(scan, options_.max_range, options_.match_range_margin), options_.node_voxel_size);
    if (loop_closure_.AddNode(scan.timestamp, node_points, pose, insertion->submap_id, insertion->submap_in_local)) {
      ApplyCorrections();
    }
  }
  return true;
}

Rigid2d ScanMatchingSlam::Match(const std::vector<Eigen::Vector2f>& points, const Rigid2d& predicted) {
  const MatchGrid& target = local_map_.target();
  ScanMatcherOptions options = options_.matcher;
  std::optional<ScanMatchResult> match;
  if (odometry_.empty()) {
    options.search = options_.no_odometry_search;
    options.refinement.prior_translation_sigma = 0.0;
    options.refinement.prior_rotation_sigma = 0.0;
  } else {
    options.use_correlative_search = false;
    match = MatchScan(points, target, nullptr, predicted, predicted, options);
    options.use_correlative_search = true;
  }
  if (!match || match->score < options_.search_below_score) {
    ++counters_.searched;
    std::optional<ScanMatchResult> searched = MatchScan(points, target, nullptr, predicted, predicted, options);
    if (searched && (!match || searched->score > match->score)) match = searched;
  }
  if (!match) {
    ++counters_.failed;
    return predicted;
  }
  ++counters_.matched;
  if (options_.max_unseen_surface_distance > 0.0 && !odometry_.empty()) {
    // Refined again without the points on surfaces the map has not seen, judged at the match
    // (not at the prediction: with poor odometry that would drop points of mapped walls).
    const std::vector<Eigen::Vector2f> seen =
        PointsOnSeenSurfaces(points, target, match->pose, options_.max_unseen_surface_distance);
    if (seen.size() < points.size()) {
      ScanMatcherOptions refine_only = options_.matcher;
      refine_only.use_correlative_search = false;
      const std::optional<ScanMatchResult> refined =
          MatchScan(seen, target, nullptr, match->pose, predicted, refine_only);
      if (refined) match = refined;
    }
  }
  if (options_.min_observed_normals > 0.0 && !odometry_.empty()) {
    const Rigid2d kept = KeepObservedDirections(predicted, match->pose, NormalScatter(points),
                                                options_.min_observed_normals);
    if ((kept.translation() - match->pose.translation()).norm() > 1e-9) ++counters_.degenerate;
    return kept;
  }
  return match->pose;
}

Rigid2d ScanMatchingSlam::CurrentPose() const {
  return trajectory_.empty() ? Rigid2d() : trajectory_.back().pose;
}

void ScanMatchingSlam::Finish() {
  submaps_.FinishActive();
  if (loop_closure_.Finish()) ApplyCorrections();
}

void ScanMatchingSlam::ApplyCorrections() {
  for (size_t i = 0; i < trajectory_.size(); ++i) {
    trajectory_[i].pose = loop_closure_.CorrectionAt(trajectory_[i].timestamp) * local_poses_[i];
  }
  ++revision_;
  submaps_moved_ = true;
}

void ScanMatchingSlam::ToCorrected(const Rigid2d& local_anchor, const Trajectory& local_poses,
                                   Submap* submap) const {
  const std::optional<Rigid2d> anchor = loop_closure_.SubmapInGlobal(submap->submap_id);
  submap->submap_in_local =
      anchor ? *anchor
             : loop_closure_.CorrectionAt(local_poses.empty() ? 0.0 : local_poses.front().timestamp) *
                   local_anchor;
  for (size_t i = 0; i < local_poses.size(); ++i) {
    submap->scan_poses[i].pose =
        loop_closure_.CorrectionAt(local_poses[i].timestamp) * local_poses[i].pose;
  }
}

namespace {

// Whether the anchor or any scan pose moved by more than what rounding could explain.
bool Moved(const Rigid2d& anchor_before, const Trajectory& poses_before, const Submap& after) {
  auto differ = [](const Rigid2d& a, const Rigid2d& b) {
    const Rigid2d delta = a.inverse() * b;
    return delta.translation().norm() > 1e-5 || std::abs(delta.rotation()) > 1e-6;
  };
  if (differ(anchor_before, after.submap_in_local)) return true;
  for (size_t i = 0; i < poses_before.size(); ++i) {
    if (differ(poses_before[i].pose, after.scan_poses[i].pose)) return true;
  }
  return false;
}

}  // namespace

std::vector<Submap> ScanMatchingSlam::TakeSubmapUpdates(size_t max_count) {
  std::vector<Submap> updates = submaps_.TakeUpdates(max_count);
  std::vector<int64_t> fresh;
  for (Submap& submap : updates) {
    const Rigid2d local_anchor = submap.submap_in_local;
    const Trajectory local_poses = submap.scan_poses;
    ToCorrected(local_anchor, local_poses, &submap);
    if (submap.finished) {
      published_[submap.submap_id] = Published{local_anchor, local_poses, submap};
      fresh.push_back(submap.submap_id);
    }
  }
  if (submaps_moved_) {
    // Finished submaps the graph moved since they were last handed out go out again; those
    // beyond max_count on a later call (they will still differ from what went out).
    submaps_moved_ = false;
    for (auto& [id, published] : published_) {
      if (updates.size() >= max_count) {
        submaps_moved_ = true;
        break;
      }
      if (std::find(fresh.begin(), fresh.end(), id) != fresh.end()) continue;
      // Only the poses are compared: copying the grid as well cost a grid per submap per call.
      const Rigid2d anchor_before = published.submap.submap_in_local;
      const Trajectory poses_before = published.submap.scan_poses;
      ToCorrected(published.local_anchor, published.local_scan_poses, &published.submap);
      if (!Moved(anchor_before, poses_before, published.submap)) continue;
      ++published.submap.revision;
      updates.push_back(published.submap);
    }
  }
  return updates;
}

bool ScanMatchingSlam::ShouldInsert(const Rigid2d& pose, double timestamp) const {
  if (!last_inserted_) return true;
  const Rigid2d delta = last_inserted_->pose.inverse() * pose;
  return delta.translation().norm() >= options_.insert_min_translation ||
         std::abs(delta.rotation()) >= options_.insert_min_rotation ||
         timestamp - last_inserted_->timestamp >= options_.insert_max_interval;
}

std::string ScanMatchingSlam::Statistics() const {
  std::ostringstream out;
  out << counters_.scans << " scans: " << counters_.matched << " matched, " << counters_.searched
      << " needed a correlative search, " << counters_.failed << " carried by odometry, " << counters_.degenerate << " kept odometry along a corridor, "
      << counters_.no_return_scans << " without returns, " << counters_.inserted
      << " inserted into the map";
  if (options_.build_submaps && options_.loop_closure.enabled) {
    out << "; loop closure: " << loop_closure_.searches() << " searches, "
        << loop_closure_.loop_constraints() << " constraints, " << loop_closure_.optimizations()
        << " optimisations";
  }
  return out.str();
}

}  // namespace fleetmap
