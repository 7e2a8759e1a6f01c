#include "map_server/merge/merge_engine.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <thread>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/trajectory_lookup.h"
#include "shared/core/thread_pool.h"

namespace fleetmap {
namespace {

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// How far (metres) the submap's corners move between two placements.
double Displacement(const OccupancyGrid& grid, const Rigid2d& a, const Rigid2d& b) {
  const Eigen::Vector2d lo = grid.origin();
  const Eigen::Vector2d hi = grid.origin() + grid.resolution() * Eigen::Vector2d(grid.width(), grid.height());
  double worst = 0.0;
  for (const Eigen::Vector2d& c : {lo, hi, Eigen::Vector2d(lo.x(), hi.y()), Eigen::Vector2d(hi.x(), lo.y())}) {
    worst = std::max(worst, (a * c - b * c).norm());
  }
  return worst;
}

// MergeEngineOptions::search_threads, 0 resolved: one per core, but no more than an update's
// nearby searches (a container may report every core of its host).
int SearchThreads(const MergeEngineOptions& options) {
  if (options.search_threads > 0) return options.search_threads;
  const int most =
      std::max(1, options.max_local_searches_per_update + options.max_loop_searches_per_update);
  return std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, most);
}

}  // namespace

const char* AlignmentEventTypeName(AlignmentEventType type) {
  switch (type) {
    case AlignmentEventType::kAlignmentAccepted: return "alignment accepted";
    case AlignmentEventType::kHypothesis: return "hypothesis";
    case AlignmentEventType::kRejected: return "rejected";
    case AlignmentEventType::kConstraintAdded: return "constraint added";
    case AlignmentEventType::kPending: return "pending";
    case AlignmentEventType::kWithdrawn: return "alignment withdrawn";
  }
  return "unknown";
}

MergeEngine::MergeEngine(const MergeEngineOptions& options)
    : options_(options),
      graph_(options.graph),
      search_pool_(std::make_unique<ThreadPool>(SearchThreads(options))) {}
MergeEngine::~MergeEngine() = default;

MergeEngine::RobotState& MergeEngine::Robot(const std::string& id) {
  auto& state = robots_[id];
  if (!state) {
    state = std::make_unique<RobotState>(options_.render_resolution);
    root_[id] = id;
  }
  return *state;
}

bool MergeEngine::AddOrUpdateSubmap(const Submap& submap, std::string* error) {
  if (submap.robot_id.empty()) return Fail(error, "submap without a robot id");
  if (submap.submap_id < 0) return Fail(error, "negative submap id");
  if (!submap.submap_in_local.IsFinite()) return Fail(error, "submap anchor is not finite");
  if (!(submap.grid.resolution() > 0.0) || !std::isfinite(submap.grid.resolution())) {
    return Fail(error, "submap grid resolution must be positive");
  }
  if (static_cast<int64_t>(submap.grid.width()) * submap.grid.height() > options_.max_render_cells) {
    return Fail(error, "submap grid is too large");
  }
  if (!IsValidTrajectory(submap.scan_poses)) return Fail(error, "submap scan poses are not in time order or not finite");
  RobotState& robot = Robot(submap.robot_id);
  const auto it = robot.submaps.find(submap.submap_id);
  if (it != robot.submaps.end()) {
    if (submap.revision < it->second.revision) {
      return Fail(error, "submap revision " + std::to_string(submap.revision) + " is older than " +
                             std::to_string(it->second.revision));
    }
    const auto rendered = robot.rendered.find(submap.submap_id);
    if (rendered != robot.rendered.end()) {
      robot.canvas.AddSubmap(it->second.grid, rendered->second.pose, -1.0f);
      robot.rendered.erase(rendered);
      ++robot.canvas_version;
    }
  }
  robot.submaps[submap.submap_id] = submap;
  robot.known_boxes[submap.submap_id] = KnownBox(submap.grid);
  robot.sources.erase(submap.submap_id);
  if (submap.finished && !submap.scan_poses.empty()) {
    // Detections near this submap's time whose search failed may succeed with it.
    const std::set<size_t> pending(pending_detections_.begin(), pending_detections_.end());
    for (const auto& [index, tries] : retry_detections_) {
      const RobotDetection& d = detections_[index];
      const double gap = std::max({0.0, submap.scan_poses.front().timestamp - d.timestamp,
                                   d.timestamp - submap.scan_poses.back().timestamp});
      if ((d.observer_id == submap.robot_id || d.observed_id == submap.robot_id) &&
          gap <= options_.source_time_window && !pending.count(index)) {
        pending_detections_.push_back(index);
      }
    }
  }
  if (submap.finished) {
    robot.cross_queue.insert(submap.submap_id);
    robot.local_queue.insert(submap.submap_id);
    robot.loop_queue.insert(submap.submap_id);
  }
  if (reference_robot_.empty()) reference_robot_ = submap.robot_id;
  return true;
}

bool MergeEngine::SetTrajectory(const std::string& robot, const Trajectory& trajectory, std::string* error) {
  if (robot.empty()) return Fail(error, "trajectory without a robot id");
  if (!IsValidTrajectory(trajectory)) return Fail(error, "trajectory is not in time order or not finite");
  Robot(robot).trajectory = trajectory;
  return true;
}

bool MergeEngine::AddDetection(const RobotDetection& detection, std::string* error) {
  if (detection.observer_id.empty() || detection.observed_id.empty()) {
    return Fail(error, "detection without observer or observed robot id");
  }
  if (detection.observer_id == detection.observed_id) return Fail(error, "a robot cannot detect itself");
  if (!std::isfinite(detection.timestamp) || !detection.position_in_observer.allFinite() ||
      !detection.covariance.allFinite()) {
    return Fail(error, "detection has non-finite values");
  }
  const Eigen::Matrix2d& c = detection.covariance;
  if (c(0, 0) <= 0.0 || c(1, 1) <= 0.0 || c.determinant() <= 0.0 || std::abs(c(0, 1) - c(1, 0)) > 1e-9) {
    return Fail(error, "detection covariance is not symmetric positive definite");
  }
  if (detection.relative_heading &&
      (!std::isfinite(*detection.relative_heading) || !(detection.relative_heading_variance > 0.0))) {
    return Fail(error, "detection heading needs a finite value and a positive variance");
  }
  detections_.push_back(detection);
  pending_detections_.push_back(detections_.size() - 1);
  return true;
}

bool MergeEngine::SetKnownPlacement(const std::string& robot, const Rigid2d& local_in_global, std::string* error) {
  if (robot.empty()) return Fail(error, "placement without a robot id");
  if (!local_in_global.IsFinite()) return Fail(error, "placement is not finite");
  for (const auto& [id, pose] : graph_.nodes()) {
    if (id.robot == robot) return Fail(error, "robot " + robot + " is already in the map; its placement can no longer change");
    if (!known_placements_.count(id.robot)) {
      return Fail(error, "the global frame is already defined by robot " + id.robot + " (unknown start)");
    }
  }
  Robot(robot);
  if (known_root_.empty()) known_root_ = robot;
  known_placements_[robot] = local_in_global;
  root_[robot] = known_root_;
  reference_robot_ = known_root_;
  return true;
}

std::string MergeEngine::Root(const std::string& robot) const {
  const auto it = root_.find(robot);
  return it == root_.end() ? robot : it->second;
}

std::vector<std::string> MergeEngine::Members(const std::string& root) const {
  std::vector<std::string> members;
  for (const auto& [robot, r] : root_) {
    if (r == root) members.push_back(robot);
  }
  return members;
}

bool MergeEngine::IsPlaced(const std::string& robot) const {
  return !reference_robot_.empty() && robots_.count(robot) && Root(robot) == Root(reference_robot_);
}

std::optional<Rigid2d> MergeEngine::LocalToFrame(const std::string& robot) const {
  const auto it = robots_.find(robot);
  if (it == robots_.end()) return std::nullopt;
  for (auto s = it->second->submaps.rbegin(); s != it->second->submaps.rend(); ++s) {
    if (const auto node = graph_.NodePose({robot, s->first})) return *node * s->second.submap_in_local.inverse();
  }
  return std::nullopt;
}

std::optional<Rigid2d> MergeEngine::RobotToGlobal(const std::string& robot) const {
  if (!IsPlaced(robot)) return std::nullopt;
  return LocalToFrame(robot);
}

std::optional<Rigid2d> MergeEngine::RobotStartToGlobal(const std::string& robot) const {
  const auto it = robots_.find(robot);
  if (!IsPlaced(robot) || it == robots_.end()) return std::nullopt;
  for (const auto& [id, submap] : it->second->submaps) {
    if (const auto node = graph_.NodePose({robot, id}))
      return *node * submap.submap_in_local.inverse();
  }
  return std::nullopt;
}

std::vector<std::string> MergeEngine::PlacedRobots() const {
  std::vector<std::string> placed;
  for (const auto& [robot, state] : robots_) {
    if (IsPlaced(robot) && !state->submaps.empty()) placed.push_back(robot);
  }
  return placed;
}

std::map<NodeId, Rigid2d> MergeEngine::SubmapPoses() const {
  std::map<NodeId, Rigid2d> poses;
  for (const auto& [id, pose] : graph_.nodes()) {
    if (IsPlaced(id.robot)) poses[id] = pose;
  }
  return poses;
}

std::vector<std::string> MergeEngine::JoinComponents(const std::string& root_a,
                                                     const std::string& root_b,
                                                     const Rigid2d& b_in_a) {
  std::string keep = root_a, drop = root_b;
  Rigid2d drop_in_keep = b_in_a;
  if (!reference_robot_.empty() && Root(reference_robot_) == root_b) {
    std::swap(keep, drop);
    drop_in_keep = b_in_a.inverse();
  }
  const std::vector<std::string> dropped = Members(drop);
  for (const std::string& member : dropped) {
    for (const auto& [id, submap] : robots_.at(member)->submaps) {
      if (const auto pose = graph_.NodePose({member, id})) graph_.SetNode({member, id}, drop_in_keep * *pose);
    }
    root_[member] = keep;
    RobotState& state = *robots_.at(member);
    state.joined_at = ++joins_;
    if (state.fixed_node) {
      graph_.SetFixed(*state.fixed_node, false);
      state.fixed_node.reset();
    }
  }
  graph_dirty_ = true;
  return dropped;
}

void MergeEngine::SyncNodes(MergeUpdate* update) {
  (void)update;
  for (auto& [robot_id, robot] : robots_) {
    std::optional<int64_t> prev;
    for (const auto& [id, submap] : robot->submaps) {
      const NodeId node{robot_id, id};
      if (!graph_.HasNode(node)) {
        std::optional<Rigid2d> pose;
        if (prev) {
          const Submap& p = robot->submaps.at(*prev);
          pose = *graph_.NodePose({robot_id, *prev}) * (p.submap_in_local.inverse() * submap.submap_in_local);
        } else if (const auto local_to_frame = LocalToFrame(robot_id)) {
          pose = *local_to_frame * submap.submap_in_local;
        } else if (const auto known = known_placements_.find(robot_id); known != known_placements_.end()) {
          pose = known->second * submap.submap_in_local;
          robot->fixed_node = node;  // every known robot holds its own start fixed
          graph_.SetFixed(node, true);
        } else {
          pose = submap.submap_in_local;  // a new component, framed by this robot's local map
        }
        graph_.SetNode(node, *pose);
        if (!robot->fixed_node && Root(robot_id) == robot_id) {
          robot->fixed_node = node;
          graph_.SetFixed(node, true);
        }
        graph_dirty_ = true;
      }
      if (prev) {
        RelativeEdge edge;
        edge.from = {robot_id, *prev};
        edge.to = node;
        edge.to_in_from = robot->submaps.at(*prev).submap_in_local.inverse() * submap.submap_in_local;
        const double length = edge.to_in_from.translation().norm();
        edge.translation_sigma = options_.odometry_translation_sigma +
                                 options_.odometry_translation_sigma_per_metre * length;
        edge.rotation_sigma = options_.odometry_rotation_sigma + options_.odometry_rotation_sigma_per_metre * length;
        edge.kind = EdgeKind::kOdometry;
        edge.robust_scale = options_.odometry_robust_scale;
        const auto e = robot->odometry_edge.find(id);
        if (e == robot->odometry_edge.end()) {
          robot->odometry_edge[id] = graph_.AddEdge(edge);
          graph_dirty_ = true;
        } else {
          const RelativeEdge& old = graph_.edges()[e->second];
          if (!(old.from == edge.from) || Displacement(submap.grid, old.to_in_from, edge.to_in_from) > 1e-6) {
            graph_.UpdateEdge(e->second, edge);
            graph_dirty_ = true;
          }
        }
      }
      prev = id;
    }
  }
}

bool MergeEngine::Solve(MergeUpdate* update) {
  if (!graph_dirty_) return false;
  const SolveSummary summary = graph_.Solve();
  update->solver_iterations += summary.iterations;
  graph_dirty_ = false;
  return summary.success;
}

void MergeEngine::RefreshCanvases(MergeUpdate* update) {
  const double threshold = options_.rerender_threshold * options_.render_resolution;
  for (auto& [robot_id, robot] : robots_) {
    const bool placed = IsPlaced(robot_id);
    for (const auto& [id, submap] : robot->submaps) {
      const auto pose = graph_.NodePose({robot_id, id});
      if (!pose) continue;
      auto rendered = robot->rendered.find(id);
      if (rendered != robot->rendered.end()) {
        if (rendered->second.revision == submap.revision &&
            Displacement(submap.grid, rendered->second.pose, *pose) < threshold) {
          continue;
        }
        if (placed) Include(&update->changed_region, robot->SubmapBounds(id, rendered->second.pose));
        robot->canvas.AddSubmap(submap.grid, rendered->second.pose, -1.0f);
      }
      robot->canvas.AddSubmap(submap.grid, *pose, 1.0f);
      robot->rendered[id] = {*pose, submap.revision};
      ++robot->canvas_version;
      if (placed) {
        Include(&update->changed_region, robot->SubmapBounds(id, *pose));
        update->moved_submaps.push_back({robot_id, id});
        update->graph_changed = true;
      }
    }
  }
}

MergeUpdate MergeEngine::Update() {
  MergeUpdate update;
  SyncNodes(&update);
  RefreshCanvases(&update);
  ProcessDetections(&update);
  if (ReviewJoins(&update)) ProcessDetections(&update);  // the withdrawn robot's, again
  if (ReviewMatchOnlyJoins(&update)) ProcessDetections(&update);
  JudgeHeldAlignments(&update);
  ReviewMatchHypotheses(&update);  // before new searches: a local check is cheap
  ProcessCrossMatches(&update);
  ProcessWholeMapMatches(&update);
  ProcessNearbyMatches(&update);
  Solve(&update);
  RefreshCanvases(&update);
  update.placed_robots = PlacedRobots();
  if (update.changed_region) update.quality = Quality(update.changed_region);
  return update;
}

}  // namespace fleetmap
