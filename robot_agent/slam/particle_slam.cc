#include "robot_agent/slam/particle_slam.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "robot_agent/slam/input_order.h"
#include "shared/matching/degeneracy.h"
#include "shared/matching/point_filter.h"

namespace fleetmap {

ParticleSlamOptions ParticleSlamOptions::FastSlam() {
  ParticleSlamOptions options;
  options.name = "fastslam";
  options.filter.proposal = ParticleProposal::kMotionModel;
  options.filter.resample_threshold = 2.0;  // every update, as in the paper's pseudo-code
  // Smaller steps than the RBPF: a motion-model proposal needs its particles close together.
  options.update_translation = 0.3;
  options.update_rotation = 0.2;
  return options;
}

ScanMatchingSlamOptions ParticleSlamOptions::DefaultTracker() {
  ScanMatchingSlamOptions options;
  options.build_submaps = false;
  options.loop_closure.enabled = false;
  return options;
}

ParticleSlamOptions ParticleSlamOptions::Rbpf() {
  ParticleSlamOptions options;
  options.name = "rbpf";
  // Loop-closure graph nodes twice as sparse as the scan-matching backend's: the same errors
  // (intel, aces, the simulator's rectangle, department and building, seeds 1-3) in about 60 %
  // of the time (intel 40-46 s -> 25 s). FastSLAM lost accuracy with them, so it keeps the
  // denser nodes (docs/BENCHMARKS.md, issue 5, session 10).
  options.loop_closure.node_min_translation = 0.2;
  options.loop_closure.node_min_rotation = 0.17;
  // The lattice on the scan-matched motion's prediction: the per-particle match's bias no
  // longer chains up (simulated building lap 1.2-10 m -> 0.10-0.25 m over 8 seeds; intel
  // 0.025 -> 0.016 m, aces 0.040 -> 0.037 m; docs/BENCHMARKS.md, issue 5, session 12).
  options.filter.centre_on_prediction = true;
  return options;
}

ParticleSlam::ParticleSlam(const ParticleSlamOptions& options)
    : options_(options),
      pool_(std::make_unique<ThreadPool>(options_.threads)),
      filter_(FilterOptions(options_), pool_.get()),
      submaps_(options.robot_id, options.keyframes_per_submap, [&] {
        OccupancyGridOptions grid = options.submap_grid;
        grid.max_trace_range = options.max_range;
        return grid;
      }()),
      tracker_([&] {
        ScanMatchingSlamOptions tracker = options.tracker;
        tracker.robot_id = options.robot_id;
        tracker.max_range = options.max_range;
        return tracker;
      }()) {
  if (options_.loop_closure.enabled) {
    loop_closure_ = std::make_unique<ParticleLoopClosure>(options_.loop_closure,
                                                          options_.keyframes_per_submap);
  }
}

ParticleFilterOptions ParticleSlam::FilterOptions(const ParticleSlamOptions& options) {
  ParticleFilterOptions filter = options.filter;
  filter.motion_noise = options.scan_matched_motion ? options.scan_matched_noise : options.odometry_noise;
  // Odometry's prediction is centimetres to decimetres off after a metre: the lattice (2.5 cm
  // steps) must then sit on the match, as in GMapping.
  filter.centre_on_prediction = options.filter.centre_on_prediction && options.scan_matched_motion;
  return filter;
}

bool ParticleSlam::AddOdometry(const StampedPose& odometry, std::string* error) {
  if (!CheckInputTime(odometry.timestamp, last_time_, "odometry", error)) return false;
  if (!odometry_.Add(odometry, error)) return false;
  if (!tracker_.AddOdometry(odometry, error)) return false;
  last_time_ = odometry.timestamp;
  return true;
}

ParticleSlam::PreparedScan ParticleSlam::Prepare(const LaserScan& scan,
                                                 const Rigid2d& pose) const {
  PreparedScan prepared;
  prepared.limited = scan;
  for (float& range : prepared.limited.ranges) {
    if (range > options_.max_range) range = LaserScan::kNoReturn;  // a masked (NaN) beam stays masked
  }
  const std::vector<Eigen::Vector2f> returns = ToPointsInRobotFrame(prepared.limited);
  const std::vector<Eigen::Vector2f> matched = InsideRecentHorizons(returns, pose);
  ParticleScan& out = prepared.filter;
  out.match_points = VoxelFilter(matched, options_.match_voxel);
  out.normal_scatter = NormalScatter(matched);
  out.weight_points = VoxelFilter(returns, options_.match_voxel);
  prepared.node_points = VoxelFilter(matched, options_.node_voxel);
  SetRays(scan, options_.max_range, &out);
  return prepared;
}

std::vector<Eigen::Vector2f> ParticleSlam::InsideRecentHorizons(
    const std::vector<Eigen::Vector2f>& returns, const Rigid2d& pose) const {
  if (keyframe_views_.empty() || keyframe_views_.size() != keyframe_poses_.size()) return returns;
  const size_t recent = static_cast<size_t>(std::max(1, options_.horizon_keyframes));
  const size_t first = keyframe_views_.size() > recent ? keyframe_views_.size() - recent : 0;
  std::vector<std::pair<Eigen::Vector2d, double>> views;  // sensor in map, squared reach
  for (size_t k = first; k < keyframe_views_.size(); ++k) {
    const double reach = std::max(
        0.0, static_cast<double>(keyframe_views_[k].horizon - options_.match_range_margin));
    views.emplace_back(keyframe_poses_[k] * keyframe_views_[k].sensor_in_robot, reach * reach);
  }
  std::vector<Eigen::Vector2f> inside;
  inside.reserve(returns.size());
  for (const Eigen::Vector2f& point : returns) {
    const Eigen::Vector2d in_map = pose * Eigen::Vector2d(point.cast<double>());
    for (const auto& [sensor, reach2] : views) {
      if ((in_map - sensor).squaredNorm() < reach2) {
        inside.push_back(point);
        break;
      }
    }
  }
  return inside;
}

bool ParticleSlam::AddScan(const LaserScan& scan, std::string* error) {
  if (!CheckInputTime(scan.timestamp, last_time_, "scan", error)) return false;
  if (!scan.sensor_in_robot.IsFinite()) {
    if (error) *error = "scan with a non-finite sensor mounting pose";
    return false;
  }
  last_time_ = scan.timestamp;
  if (!tracker_.AddScan(scan, error)) return false;
  const Rigid2d tracker_pose = tracker_.CurrentPose();
  const std::optional<Rigid2d> odometry = odometry_.PoseAt(scan.timestamp);
  Rigid2d odometry_delta;
  if (odometry && last_odometry_) odometry_delta = last_odometry_->inverse() * *odometry;
  if (odometry) last_odometry_ = odometry;

  // The tracker's motion since the latest keyframe, from that keyframe's pose.
  if (filter_.initialized()) {
    current_pose_ = keyframe_poses_.back() * (tracker_at_keyframe_.inverse() * tracker_pose);
  }
  PreparedScan prepared = Prepare(scan, current_pose_);
  const ParticleScan& filter_scan = prepared.filter;
  if (!filter_.initialized()) {
    if (filter_scan.weight_points.empty()) {
      // Nothing to start a map with yet: the robot stays at the origin.
      trajectory_.push_back({scan.timestamp, current_pose_});
      anchors_.push_back({0, current_pose_});
      return true;
    }
    filter_.Initialize(current_pose_, filter_scan);
    AddKeyframe(prepared.limited, tracker_pose);
  } else {
    odometry_since_update_ = odometry_since_update_ * odometry_delta;
    const Rigid2d tracked_motion = keyframe_poses_.back().inverse() * current_pose_;
    const Rigid2d motion = options_.scan_matched_motion ? tracked_motion : odometry_since_update_;
    if (!filter_scan.weight_points.empty() &&
        (motion.translation().norm() >= options_.update_translation ||
         std::abs(motion.rotation()) >= options_.update_rotation)) {
      filter_.Update(motion, tracked_motion, filter_scan);
      odometry_since_update_ = Rigid2d();
      AddKeyframe(prepared.limited, tracker_pose);
    }
  }
  anchors_.push_back({keyframe_poses_.size() - 1, keyframe_poses_.back().inverse() * current_pose_});
  if (loop_closure_) {
    loop_closure_->AddScan(scan.timestamp, anchors_.back().keyframe, anchors_.back().offset,
                           std::move(prepared.node_points));
  }
  trajectory_.push_back({scan.timestamp, current_pose_});
  trajectory_.back().pose = ReportedPose(trajectory_.size() - 1);
  return true;
}

void ParticleSlam::AddKeyframe(const LaserScan& limited, const Rigid2d& tracker_pose) {
  keyframe_views_.push_back({limited.sensor_in_robot.translation(), Horizon(limited, options_.max_range)});
  submaps_.AddKeyframe(limited);
  tracker_at_keyframe_ = tracker_pose;
  RefreshBestHistory();
  current_pose_ = keyframe_poses_.back();
}

// Takes the best particle's keyframe history; when its earlier part changed (resampling or a
// different best particle), every scan pose is re-derived from its keyframe and the trajectory
// revision grows.
void ParticleSlam::RefreshBestHistory() {
  std::vector<Rigid2d> history = filter_.History(filter_.best_index());
  bool changed = false;
  for (size_t i = 0; i < keyframe_poses_.size() && i < history.size(); ++i) {
    if (!(keyframe_poses_[i].translation() == history[i].translation()) ||
        keyframe_poses_[i].rotation() != history[i].rotation()) {
      changed = true;
      break;
    }
  }
  keyframe_poses_ = std::move(history);
  if (loop_closure_) {
    SettleAndCorrect(changed);
    return;
  }
  submaps_.SetPoses(keyframe_poses_);
  if (!changed) return;
  ++revision_;
  ReportAllPoses();
}

// Hands the keyframes that settled to the loop-closure layer; the reported poses move when the
// filter changed its unsettled history or the pose graph its corrections.
void ParticleSlam::SettleAndCorrect(bool history_changed) {
  const size_t settled_before = loop_closure_->settled();
  const int64_t shared =
      NewestSharedKeyframe(filter_.particles(), static_cast<int64_t>(settled_before));
  const bool corrected = loop_closure_->Update(keyframe_poses_, shared);
  submaps_.SetPoses(loop_closure_->LocalKeyframePoses(keyframe_poses_));
  if (!history_changed && !corrected) return;
  ++revision_;
  if (corrected) {
    ReportAllPoses();
    return;
  }
  // The layer ignores the filter's changes to settled keyframes: only later scans move.
  for (size_t i = anchors_.size(); i-- > 0 && anchors_[i].keyframe >= settled_before;) {
    trajectory_[i].pose = ReportedPose(i);
  }
}

Rigid2d ParticleSlam::ReportedPose(size_t scan) const {
  const ScanAnchor& anchor = anchors_[scan];
  if (anchor.keyframe >= keyframe_poses_.size()) return trajectory_[scan].pose;
  if (!loop_closure_) return keyframe_poses_[anchor.keyframe] * anchor.offset;
  const Rigid2d local =
      loop_closure_->LocalKeyframePose(anchor.keyframe, keyframe_poses_) * anchor.offset;
  return loop_closure_->Corrected(trajectory_[scan].timestamp, local);
}

void ParticleSlam::ReportAllPoses() {
  for (size_t i = 0; i < anchors_.size(); ++i) trajectory_[i].pose = ReportedPose(i);
}

Rigid2d ParticleSlam::CurrentPose() const {
  if (!loop_closure_) return current_pose_;
  return trajectory_.empty() ? Rigid2d() : trajectory_.back().pose;
}

std::vector<Submap> ParticleSlam::TakeSubmapUpdates(size_t max_count) {
  std::vector<Submap> updates = submaps_.TakeUpdates(max_count);
  if (!loop_closure_) return updates;
  // Submaps the pose graph moved go out again, rendered anew (no grid is kept meanwhile).
  for (int64_t id : loop_closure_->TakeMovedSubmaps()) moved_submaps_.insert(id);
  for (const Submap& submap : updates) moved_submaps_.erase(submap.submap_id);
  while (updates.size() < max_count && !moved_submaps_.empty()) {
    const int64_t id = *moved_submaps_.begin();
    moved_submaps_.erase(moved_submaps_.begin());
    std::optional<Submap> again = submaps_.RenderPublished(id);
    if (again) updates.push_back(std::move(*again));
  }
  for (Submap& submap : updates) loop_closure_->CorrectSubmap(&submap);
  return updates;
}

void ParticleSlam::Finish() {
  submaps_.Finish();
  if (!loop_closure_) return;
  // Every particle's history is final now: all keyframes settle and the graph closes.
  loop_closure_->Finish(keyframe_poses_);
  submaps_.SetPoses(loop_closure_->LocalKeyframePoses(keyframe_poses_));
  ++revision_;
  ReportAllPoses();
}

std::string ParticleSlam::Statistics() const {
  std::ostringstream out;
  out << options_.name << ": " << trajectory_.size() << " scans, " << keyframe_poses_.size() << " keyframes, "
      << filter_.particles().size() << " particles, " << filter_.resamplings() << " resamplings, "
      << filter_.proposal_fallbacks() << " proposal fallbacks to the motion model, " << revision_
      << " trajectory revisions; map tiles "
      << filter_.UniqueTileBytes() / (1024 * 1024) << " MiB unique of "
      << filter_.TotalTileBytes() / (1024 * 1024) << " MiB referenced";
  if (loop_closure_) out << "; " << loop_closure_->Statistics();
  out << "; tracker: " << tracker_.Statistics();
  return out.str();
}

}  // namespace fleetmap
