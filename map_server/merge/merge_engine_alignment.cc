// MergeEngine: evidence (detections, cross-robot matches) into hypotheses, alignments and
// constraints.

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "map_server/merge/grid_points.h"
#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"
#include "map_server/merge/trajectory_lookup.h"

namespace fleetmap {
namespace {

// Added to a detection's relative-heading variance (rad^2): our own headings are not exact.
constexpr double kHeadingVarianceFloor = 1e-4;

Eigen::Vector2d GridCenter(const OccupancyGrid& grid) {
  return grid.origin() + 0.5 * grid.resolution() * Eigen::Vector2d(grid.width(), grid.height());
}

}  // namespace

std::optional<Rigid2d> MergeEngine::RobotInComponent(const std::string& robot, double time) const {
  const auto at = PoseAtTime(robot, time);
  if (!at) return std::nullopt;
  const auto node = graph_.NodePose({robot, at->host_submap});
  if (!node) return std::nullopt;
  return *node * at->robot_in_node;
}

double MergeEngine::DetectionDistance(const RobotDetection& d, const Rigid2d& observer,
                                      const Rigid2d& observed) const {
  const double floor2 = options_.detection_sigma_floor * options_.detection_sigma_floor;
  const Eigen::Matrix2d covariance = d.covariance + floor2 * Eigen::Matrix2d::Identity();
  const Eigen::Vector2d error = observer.inverse() * observed.translation() - d.position_in_observer;
  double m = std::sqrt(error.dot(covariance.inverse() * error));
  if (d.relative_heading) {
    const double dh = NormalizeAngle(observed.rotation() - observer.rotation() - *d.relative_heading);
    m = std::max(m, std::abs(dh) / std::sqrt(d.relative_heading_variance + kHeadingVarianceFloor));
  }
  return m;
}

std::optional<MergeEngine::TimedPose> MergeEngine::PoseAtTime(const std::string& robot, double time) const {
  const auto it = robots_.find(robot);
  if (it == robots_.end() || it->second->submaps.empty()) return std::nullopt;
  const RobotState& state = *it->second;
  // The host is the submap whose scans span the time, else the one closest in time.
  int64_t host = -1;
  double best = 1e300;
  for (const auto& [id, submap] : state.submaps) {
    if (submap.scan_poses.empty() || !graph_.HasNode({robot, id})) continue;
    const double gap = std::max({0.0, submap.scan_poses.front().timestamp - time,
                                 time - submap.scan_poses.back().timestamp});
    if (gap < best) {
      best = gap;
      host = id;
    }
  }
  if (host < 0 || best > options_.source_time_window) return std::nullopt;
  // The pose comes from the host's own scan poses when they cover the time: they belong to the
  // same revision as its anchor. The trajectory and the submaps are revised separately (a loop
  // closure on the robot re-publishes the submaps it moved at once, the trajectory every few
  // seconds), and a pose from one revision against an anchor from another moves the detection
  // by the whole correction.
  const Submap& hosting = state.submaps.at(host);
  std::optional<Rigid2d> local = PoseAt(hosting.scan_poses, time, options_.trajectory_max_gap);
  if (!local) local = PoseAt(state.trajectory, time, options_.trajectory_max_gap);
  for (auto it = state.submaps.begin(); !local && it != state.submaps.end(); ++it) {
    local = PoseAt(it->second.scan_poses, time, options_.trajectory_max_gap);
  }
  if (!local) return std::nullopt;
  return TimedPose{host, hosting.submap_in_local.inverse() * *local};
}

const MatchSource& MergeEngine::SubmapSource(const std::string& robot, int64_t submap_id) {
  RobotState& state = *robots_.at(robot);
  const Submap& submap = state.submaps.at(submap_id);
  auto it = state.sources.find(submap_id);
  if (it == state.sources.end() || it->second.first != submap.revision) {
    state.sources[submap_id] = {submap.revision, MakeMatchSource(submap.grid, Rigid2d(), options_.match)};
    it = state.sources.find(submap_id);
  }
  return it->second.second;
}

std::string MergeEngine::CanvasStamp(const std::string& root) const {
  return PartStamp(Members(root));
}

std::string MergeEngine::PartStamp(const Part& members) const {
  std::ostringstream stamp;
  for (const std::string& m : members) stamp << m << ':' << robots_.at(m)->canvas_version << ';';
  return stamp.str();
}

std::string MergeEngine::PartKey(const Part& members) {
  std::string key;
  for (const std::string& m : members) key += m + ';';
  return key;
}

const MatchTarget& MergeEngine::Target(const std::string& root) {
  const std::string stamp = CanvasStamp(root);
  CachedTarget& cached = targets_[root];
  if (!cached.target || cached.stamp != stamp) {
    LogOddsCanvas sum(options_.render_resolution);
    for (const std::string& m : Members(root)) sum.AddCanvas(robots_.at(m)->canvas);
    cached.target = std::make_unique<MatchTarget>(sum.ToGrid(options_.render_grid), options_.match);
    cached.stamp = stamp;
  }
  return *cached.target;
}

std::unique_ptr<MatchTarget> MergeEngine::CroppedTarget(const std::string& root, const std::string& excluded,
                                                        const Box2d& box) const {
  LogOddsCanvas sum(options_.render_resolution);
  for (const std::string& m : Members(root)) {
    if (m != excluded) sum.AddCanvas(robots_.at(m)->canvas, box);
  }
  return std::make_unique<MatchTarget>(sum.ToGrid(options_.render_grid, box), options_.match);
}

std::optional<NodeId> MergeEngine::NearestNode(const std::string& root, const std::string& excluded,
                                               const Eigen::Vector2d& point_in_frame) const {
  std::optional<NodeId> nearest;
  double best = 1e300;
  for (const std::string& m : Members(root)) {
    if (m == excluded) continue;
    for (const auto& [id, submap] : robots_.at(m)->submaps) {
      const auto pose = graph_.NodePose({m, id});
      if (!pose) continue;
      const double d = (*pose * GridCenter(submap.grid) - point_in_frame).norm();
      if (d < best) {
        best = d;
        nearest = NodeId{m, id};
      }
    }
  }
  return nearest;
}

RelativeEdge MergeEngine::MatchEdge(const NodeId& from, const NodeId& to, EdgeKind kind) const {
  RelativeEdge edge;
  edge.from = from;
  edge.to = to;
  edge.to_in_from = graph_.NodePose(from)->inverse() * *graph_.NodePose(to);
  const bool loop = kind == EdgeKind::kLoopClosure;
  edge.translation_sigma =
      loop ? options_.loop_translation_sigma : options_.match_translation_sigma;
  edge.rotation_sigma = loop ? options_.loop_rotation_sigma : options_.match_rotation_sigma;
  edge.kind = kind;
  edge.robust_scale = options_.robust_scale;
  return edge;
}

Rigid2d MergeEngine::FrameTransform(const Hypothesis& h) const {
  return *LocalToFrame(h.robot_a) * h.local_b_in_local_a * LocalToFrame(h.robot_b)->inverse();
}

bool MergeEngine::Agree(const Hypothesis& a, const Hypothesis& b) const {
  // Two different detections are independent evidence even when they share submaps; two
  // submap matches are independent only when they used different submaps.
  if (a.detection && b.detection && *a.detection == *b.detection) return false;
  if (a.detection && b.detection && a.robot_b == b.robot_b &&
      (a.observed_in_local - b.observed_in_local).norm() < options_.min_detection_baseline) {
    return false;
  }
  if ((!a.detection || !b.detection) && a.robot_b == b.robot_b) {
    for (int64_t id : a.submaps_b) {
      if (b.submaps_b.count(id)) return false;
    }
  }
  // Nor is the same pair of submaps matched the other way round (b's submap landing on a's node
  // that a matched): where one match slides along a corridor, its reverse slides with it.
  auto matched = [](const Hypothesis& h, const NodeId& node) {
    return node.robot == h.robot_b && h.submaps_b.count(node.submap) > 0;
  };
  if ((!a.detection || !b.detection) && (matched(a, b.edge.from) || matched(b, a.edge.from))) {
    return false;
  }
  return SameAlignment(a, b);
}

bool MergeEngine::SameAlignment(const Hypothesis& a, const Hypothesis& b) const {
  const std::string ra = Root(a.robot_a), rb = Root(a.robot_b);
  Rigid2d fb = FrameTransform(b);
  if (Root(b.robot_a) == rb && Root(b.robot_b) == ra) {
    fb = fb.inverse();
  } else if (Root(b.robot_a) != ra || Root(b.robot_b) != rb) {
    return false;
  }
  const Rigid2d fa = FrameTransform(a);
  const Eigen::Vector2d p = graph_.NodePose(a.edge.to)->translation();  // in the b frame
  return (fa * p - fb * p).norm() <= options_.agreement_translation &&
         std::abs(NormalizeAngle(fa.rotation() - fb.rotation())) <= options_.agreement_rotation;
}

void MergeEngine::ProcessDetections(MergeUpdate* update) {
  std::vector<size_t> still_pending;
  for (size_t index : pending_detections_) {
    bool keep = false;
    ProcessDetection(index, update, &keep);
    if (keep) still_pending.push_back(index);
  }
  while (still_pending.size() > options_.max_pending_detections) {
    AlignmentEvent event;
    event.type = AlignmentEventType::kRejected;
    event.detection_index = still_pending.front();
    event.robot_a = detections_[still_pending.front()].observer_id;
    event.robot_b = detections_[still_pending.front()].observed_id;
    event.reason = "dropped: too many detections waiting for poses";
    update->events.push_back(event);
    still_pending.erase(still_pending.begin());
  }
  pending_detections_ = std::move(still_pending);
}

void MergeEngine::ProcessDetection(size_t index, MergeUpdate* update, bool* keep_pending) {
  const RobotDetection& d = detections_[index];
  AlignmentEvent event;
  event.evidence = EvidenceKind::kDetection;
  event.robot_a = d.observer_id;
  event.robot_b = d.observed_id;
  event.detection_index = index;
  const auto a = PoseAtTime(d.observer_id, d.timestamp);
  const auto b = PoseAtTime(d.observed_id, d.timestamp);
  if (!a || !b) {
    *keep_pending = true;
    if (pending_reported_.insert(index).second) {
      event.type = AlignmentEventType::kPending;
      event.reason = "waiting for both robots' poses at the detection time";
      update->events.push_back(event);
    }
    return;
  }
  const NodeId node_a{d.observer_id, a->host_submap}, node_b{d.observed_id, b->host_submap};
  const Rigid2d a_robot = *graph_.NodePose(node_a) * a->robot_in_node;  // in Root(a) frame
  const Rigid2d b_robot = *graph_.NodePose(node_b) * b->robot_in_node;  // in Root(b) frame
  DetectionEdge detection_edge;
  detection_edge.observer = node_a;
  detection_edge.observed = node_b;
  detection_edge.observer_robot_in_node = a->robot_in_node;
  detection_edge.observed_robot_in_node = b->robot_in_node;
  detection_edge.position = d.position_in_observer;
  const double floor2 = options_.detection_sigma_floor * options_.detection_sigma_floor;
  detection_edge.covariance = d.covariance + floor2 * Eigen::Matrix2d::Identity();
  detection_edge.relative_heading = d.relative_heading;
  detection_edge.heading_variance = d.relative_heading_variance + kHeadingVarianceFloor;
  detection_edge.robust_scale = options_.robust_scale;

  if (Root(d.observer_id) == Root(d.observed_id)) {
    // Joined already: the detection is a constraint if it agrees with the map, else an outlier.
    const Eigen::Vector2d error = a_robot.inverse() * b_robot.translation() - d.position_in_observer;
    const double m = DetectionDistance(d, a_robot, b_robot);
    event.residual = error.norm();
    std::ostringstream os;
    os.precision(3);
    os << "Mahalanobis distance " << m << " to the current alignment (position error " << error.norm() << " m)";
    if (m <= options_.detection_gate) {
      graph_.AddDetection(detection_edge);
      graph_dirty_ = true;
      event.type = AlignmentEventType::kConstraintAdded;
      event.reason = os.str();
    } else {
      event.type = AlignmentEventType::kRejected;
      event.reason = "inconsistent with the accepted alignment: " + os.str();
      review_joins_ = true;
    }
    update->events.push_back(event);
    return;
  }

  // Not joined yet: resolve the relative heading by matching the seen robot's submaps near
  // that time (in its robot frame) around the detected position in the observer's map.
  MatchSource source;
  std::vector<std::pair<double, int64_t>> near;
  for (const auto& [id, submap] : robots_.at(d.observed_id)->submaps) {
    if (submap.scan_poses.empty()) continue;
    const double gap = std::max({0.0, submap.scan_poses.front().timestamp - d.timestamp,
                                 d.timestamp - submap.scan_poses.back().timestamp});
    if (gap <= options_.source_time_window) near.emplace_back(gap, id);
  }
  std::sort(near.begin(), near.end());
  near.resize(std::min<size_t>(near.size(), 3));
  for (const auto& [gap, id] : near) {
    MatchSource part = SubmapSource(d.observed_id, id);
    const Rigid2d to_robot = b_robot.inverse() * *graph_.NodePose({d.observed_id, id});
    TransformSource(to_robot, &part);
    AppendSource(part, &source);
    event.submaps_b.push_back(id);
  }
  ThinSource(options_.render_resolution, options_.match, &source);

  SearchWindow window;
  const double sigma = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(d.covariance).eigenvalues().maxCoeff());
  const double half = std::clamp(options_.detection_window_sigmas * sigma, options_.detection_window_min,
                                 options_.detection_window_max);
  window.linear_half_extent = Eigen::Vector2d::Constant(half);
  // The heading: measured, else from the seen robot's motion, else the full circle.
  const std::optional<HeadingPrior> prior = d.relative_heading ? std::nullopt : HeadingFromMotion(index);
  double heading = 0.0, heading_half = M_PI;
  if (d.relative_heading) {
    heading = a_robot.rotation() + *d.relative_heading;
    heading_half = options_.detection_window_sigmas * std::sqrt(d.relative_heading_variance);
  } else if (prior) {
    heading = prior->heading + b_robot.rotation();
    heading_half = options_.detection_window_sigmas * prior->sigma;
  }
  window.center = Rigid2d(a_robot * d.position_in_observer, heading);
  window.angular_half_extent = heading_half < M_PI ? std::max(heading_half, options_.heading_window_min) : M_PI;
  const Box2d box = Grow(Box2d{window.center.translation(), window.center.translation()},
                         Radius(source.coarse) + half + 1.0);
  const auto target = CroppedTarget(Root(d.observer_id), "", box);
  const MatchResult r = target->Match(source, window, options_.detection_gates);
  FillEvent(r, &event);
  if (prior) {
    std::ostringstream os;
    os.precision(3);
    os << "; heading within +-" << window.angular_half_extent * 180.0 / M_PI
       << " deg of the seen robot's motion";
    event.reason += os.str();
  }
  if (!r.accepted) {
    event.type = AlignmentEventType::kRejected;
    int& tries = retry_detections_[index];
    if (++tries <= options_.max_detection_retries) {
      event.reason += "; tried again when more of their maps arrive";
    } else {
      retry_detections_.erase(index);
    }
    update->events.push_back(event);
    return;
  }
  retry_detections_.erase(index);
  const Rigid2d b_frame_in_a_frame = r.pose * b_robot.inverse();
  Hypothesis h;
  h.robot_a = d.observer_id;
  h.robot_b = d.observed_id;
  h.local_b_in_local_a =
      LocalToFrame(h.robot_a)->inverse() * b_frame_in_a_frame * *LocalToFrame(h.robot_b);
  h.detection = index;
  h.observed_in_local =
      (robots_.at(d.observed_id)->submaps.at(b->host_submap).submap_in_local * b->robot_in_node).translation();
  h.submaps_b.insert(event.submaps_b.begin(), event.submaps_b.end());
  const NodeId from = *NearestNode(Root(d.observer_id), "", r.pose.translation());
  h.edge = MatchedEdge(from, node_b, b_frame_in_a_frame * *graph_.NodePose(node_b),
                       EdgeKind::kDetectionMatch);
  h.detection_edge = detection_edge;
  event.local_b_in_local_a = h.local_b_in_local_a;
  h.event = event;
  Consider(std::move(h), update);
}

}  // namespace fleetmap
