#include "robot_agent/slam/loop_closure.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <thread>
#include <utility>

#include "shared/matching/degeneracy.h"
#include "shared/matching/point_filter.h"

namespace fleetmap {

MatchGridOptions LoopClosureOptions::DefaultGrid() {
  MatchGridOptions options;
  options.track_observed = true;
  return options;
}

CorrelativeSearchOptions LoopClosureOptions::DefaultSearch() {
  CorrelativeSearchOptions options;
  options.linear_window = 5.0;
  options.angular_window = 0.2;
  // Coarser than one cell at the farthest point (which would be ~0.2 degree): refinement
  // recovers the rest, and the search's cost is proportional to the number of angles.
  options.angular_step = 0.01;
  options.min_score = 0.6;
  return options;
}

PoseRefinementOptions LoopClosureOptions::DefaultRefinement() {
  PoseRefinementOptions options;
  options.prior_translation_sigma = 0.0;  // the match stands on its own
  options.prior_rotation_sigma = 0.0;
  return options;
}

LoopClosure::LoopClosure(const LoopClosureOptions& options) : options_(options) {}

namespace {

// The points (robot frame) that land, at `robot_in_submap`, in cells the submap's scans saw.
std::vector<Eigen::Vector2f> PointsLandingOnSeenCells(const std::vector<Eigen::Vector2f>& points,
                                                      const MatchGrid& grid, const Rigid2d& robot_in_submap) {
  std::vector<Eigen::Vector2f> seen;
  seen.reserve(points.size());
  for (const Eigen::Vector2f& p : points) {
    if (grid.Observed(robot_in_submap * Eigen::Vector2d(p.cast<double>()))) seen.push_back(p);
  }
  return seen;
}

}  // namespace

int LoopClosure::SubmapIndex(int64_t submap_id, const Rigid2d& submap_in_local) {
  const auto found = submap_index_.find(submap_id);
  if (found != submap_index_.end()) return found->second;
  // A new submap: the previous one is finished, so it becomes a loop-closure target.
  if (!submaps_.empty() && !submaps_.back().finished && !submaps_.back().grid->empty()) {
    submaps_.back().finished = true;
    Target(submaps_.size() - 1);
  }
  const Rigid2d correction = nodes_.empty() ? Rigid2d() : NodeCorrection(nodes_.size() - 1);
  SubmapEntry entry;
  entry.id = submap_id;
  entry.local = submap_in_local;
  entry.global = correction * submap_in_local;
  entry.grid = std::make_shared<MatchGrid>(options_.grid);
  submaps_.push_back(std::move(entry));
  const int index = static_cast<int>(submaps_.size()) - 1;
  submap_index_[submap_id] = index;
  return index;
}

bool LoopClosure::AddNode(double timestamp, const std::vector<Eigen::Vector2f>& points_in_robot,
                          const Rigid2d& robot_in_local, int64_t submap_id,
                          const Rigid2d& submap_in_local) {
  if (!robot_in_local.IsFinite() || !submap_in_local.IsFinite()) return false;
  const int submap = SubmapIndex(submap_id, submap_in_local);
  const Rigid2d correction = nodes_.empty() ? Rigid2d() : NodeCorrection(nodes_.size() - 1);
  const double travel =
      nodes_.empty() ? 0.0
                     : nodes_.back().travel +
                           (robot_in_local.translation() - nodes_.back().local.translation()).norm();
  nodes_.push_back({timestamp, robot_in_local, correction * robot_in_local, submap, travel});
  const int node = static_cast<int>(nodes_.size()) - 1;

  SubmapEntry& entry = submaps_[static_cast<size_t>(submap)];
  const std::vector<Eigen::Vector2f> points = RangeFilter(points_in_robot, options_.max_range);
  const Rigid2d robot_in_submap = entry.local.inverse() * robot_in_local;
  entry.grid->AddPoints(points, robot_in_submap);
  entry.scans.push_back({points, robot_in_submap});
  entry.centre_sum += robot_in_submap.translation();
  ++entry.node_count;
  entry.linked_travel = travel;

  if (!options_.enabled) return false;
  if (options_.search_every_nodes > 0 && node % options_.search_every_nodes == 0) {
    SearchLoops(node, points);
    ConfirmCandidates();
  }
  if (loops_.size() > loops_at_last_optimization_ &&
      nodes_.size() >= nodes_at_last_optimization_ + static_cast<size_t>(options_.optimize_every_nodes)) {
    return Optimize();
  }
  return false;
}

bool LoopClosure::Finish() {
  if (!options_.enabled || loops_.size() == loops_at_last_optimization_) return false;
  return Optimize();
}

const LoopClosure::SubmapEntry& LoopClosure::Target(size_t index) {
  SubmapEntry& entry = submaps_[index];
  entry.last_used = static_cast<uint64_t>(searches_) + 1;
  if (entry.pyramid) return entry;
  if (!entry.grid) {
    entry.grid = std::make_shared<MatchGrid>(options_.grid);
    for (const InsertedScan& scan : entry.scans) entry.grid->AddPoints(scan.points, scan.robot_in_submap);
    ++target_rebuilds_;
  }
  entry.pyramid = std::make_shared<const MatchGridPyramid>(*entry.grid, options_.pyramid_levels);
  ++cached_targets_;
  while (options_.max_cached_targets > 0 && cached_targets_ > options_.max_cached_targets) {
    SubmapEntry* oldest = nullptr;
    for (SubmapEntry& other : submaps_) {
      if (&other == &entry || !other.pyramid) continue;
      if (!oldest || other.last_used < oldest->last_used) oldest = &other;
    }
    if (!oldest) break;
    oldest->grid.reset();
    oldest->pyramid.reset();
    --cached_targets_;
  }
  return entry;
}

void LoopClosure::SearchLoops(int node, const std::vector<Eigen::Vector2f>& points) {
  if (points.empty()) return;
  if (options_.min_observed_normals > 0.0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(NormalScatter(points));
    if (solver.eigenvalues()(0) < options_.min_observed_normals) return;
  }
  const Node& n = nodes_[static_cast<size_t>(node)];
  const int64_t own_id = submaps_[static_cast<size_t>(n.submap)].id;
  std::vector<std::pair<double, size_t>> nearby;  // (distance, submap index)
  for (size_t s = 0; s < submaps_.size(); ++s) {
    const SubmapEntry& target = submaps_[s];
    if (!target.finished || target.id > own_id - options_.min_submap_gap) continue;
    const Eigen::Vector2d centre =
        target.global * Eigen::Vector2d(target.centre_sum / std::max(1, target.node_count));
    const double distance = (centre - n.global.translation()).norm();
    if (distance <= options_.max_search_distance) nearby.emplace_back(distance, s);
  }
  std::sort(nearby.begin(), nearby.end());
  if (options_.max_submaps_per_search > 0 &&
      nearby.size() > static_cast<size_t>(options_.max_submaps_per_search)) {
    nearby.resize(static_cast<size_t>(options_.max_submaps_per_search));
  }
  // Targets are fetched in order (the cache's bookkeeping stays on this thread); the searches
  // then run concurrently and their matches are kept in that order, so the result does not
  // depend on the thread count.
  std::vector<Search> searches;
  for (const auto& [distance, s] : nearby) {
    const SubmapEntry& target = Target(s);
    ++searches_;
    CorrelativeSearchOptions window = options_.search;
    window.linear_window =
        std::min(window.linear_window,
                 options_.min_linear_window +
                     options_.linear_window_per_metre * (n.travel - target.linked_travel));
    searches.push_back({target.grid, target.pyramid, target.global.inverse() * n.global, window});
  }
  if (searches.empty()) return;
  const std::vector<Eigen::Vector2f> search_points = VoxelFilter(points, options_.search_voxel_size);
  std::vector<std::optional<Rigid2d>> matches(searches.size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i = next++; i < searches.size(); i = next++) {
      matches[i] = Match(points, search_points, searches[i]);
    }
  };
  const size_t threads =
      std::min<size_t>(searches.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> helpers;
  for (size_t t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  for (size_t i = 0; i < nearby.size(); ++i) {
    if (!matches[i]) continue;
    candidates_.push_back({node, static_cast<int>(nearby[i].second), *matches[i]});
    ++candidate_count_;
  }
}

std::optional<Rigid2d> LoopClosure::Match(const std::vector<Eigen::Vector2f>& points,
                                          const std::vector<Eigen::Vector2f>& search_points,
                                          const Search& search) const {
  const std::optional<CorrelativeMatch> coarse =
      SearchBranchAndBound(search_points, *search.pyramid, search.guess, search.window);
  if (!coarse) return std::nullopt;
  const std::vector<Eigen::Vector2f> seen = PointsLandingOnSeenCells(points, *search.grid, coarse->pose);
  if (seen.size() < options_.min_observed_fraction * static_cast<double>(points.size())) {
    return std::nullopt;
  }
  const PoseRefinement refined =
      RefinePose(seen, *search.grid, coarse->pose, coarse->pose, options_.refinement);
  if (!refined.pose.IsFinite() || refined.score < options_.min_refined_score ||
      refined.inlier_fraction < options_.min_inlier_fraction) {
    return std::nullopt;
  }
  // Beams start at the robot's origin, as they did when the target's seen space was marked.
  const double behind = WallsSeenFromBehind(points, Eigen::Vector2d::Zero(), *search.grid,
                                            refined.pose, options_.seen_from_behind)
                            .fraction();
  if (behind > options_.max_seen_from_behind) return std::nullopt;
  return refined.pose;
}

bool LoopClosure::Agree(const Loop& a, const Loop& b) const {
  auto correction = [&](const Loop& loop) {
    const Rigid2d match = submaps_[static_cast<size_t>(loop.submap)].global * loop.node_in_submap;
    return match * nodes_[static_cast<size_t>(loop.node)].global.inverse();
  };
  const Rigid2d ca = correction(a), cb = correction(b);
  const Eigen::Vector2d between = 0.5 * (nodes_[static_cast<size_t>(a.node)].global.translation() +
                                         nodes_[static_cast<size_t>(b.node)].global.translation());
  return (ca * between - cb * between).norm() <= options_.agreement_translation &&
         std::abs(NormalizeAngle(ca.rotation() - cb.rotation())) <= options_.agreement_rotation;
}

void LoopClosure::ConfirmCandidates() {
  const int newest = static_cast<int>(nodes_.size()) - 1;
  candidates_.erase(std::remove_if(candidates_.begin(), candidates_.end(),
                                   [&](const Loop& c) {
                                     return c.node < newest - options_.candidate_lifetime_nodes;
                                   }),
                    candidates_.end());
  for (Loop& candidate : candidates_) {
    if (candidate.accepted) continue;
    int agreeing = 0;
    for (const Loop& other : candidates_) agreeing += Agree(candidate, other) ? 1 : 0;
    if (agreeing < options_.min_agreeing) continue;
    candidate.accepted = true;
    loops_.push_back(candidate);
    SubmapEntry& target = submaps_[static_cast<size_t>(candidate.submap)];
    target.linked_travel = std::max(target.linked_travel, nodes_[static_cast<size_t>(candidate.node)].travel);
  }
}

bool LoopClosure::Optimize() {
  loops_at_last_optimization_ = loops_.size();
  nodes_at_last_optimization_ = nodes_.size();
  if (!Solve()) return false;
  if (DropInconsistentLoops() > 0 && !Solve()) return false;
  loops_at_last_optimization_ = loops_.size();
  ++optimizations_;
  return true;
}

int LoopClosure::DropInconsistentLoops() {
  const size_t before = loops_.size();
  loops_.erase(std::remove_if(loops_.begin(), loops_.end(),
                              [&](const Loop& loop) {
                                const Rigid2d solved = submaps_[static_cast<size_t>(loop.submap)].global.inverse() *
                                                       nodes_[static_cast<size_t>(loop.node)].global;
                                const Rigid2d error = loop.node_in_submap.inverse() * solved;
                                return error.translation().norm() > options_.max_loop_residual_translation ||
                                       std::abs(error.rotation()) > options_.max_loop_residual_rotation;
                              }),
               loops_.end());
  const int dropped = static_cast<int>(before - loops_.size());
  dropped_ += dropped;
  return dropped;
}

bool LoopClosure::Solve() {
  const int node_count = static_cast<int>(nodes_.size());
  std::vector<Rigid2d> poses;
  poses.reserve(nodes_.size() + submaps_.size());
  for (const Node& n : nodes_) poses.push_back(n.global);
  for (const SubmapEntry& s : submaps_) poses.push_back(s.global);
  std::vector<PoseGraphConstraint> constraints;
  constraints.reserve(2 * nodes_.size() + loops_.size());
  auto local = [&](int from, int to, const Rigid2d& relative) {
    constraints.push_back({from, to, relative, options_.local_translation_sigma,
                           options_.local_rotation_sigma, 0.0});
  };
  for (int i = 0; i < node_count; ++i) {
    const Node& n = nodes_[static_cast<size_t>(i)];
    const SubmapEntry& s = submaps_[static_cast<size_t>(n.submap)];
    local(node_count + n.submap, i, s.local.inverse() * n.local);
    if (i > 0) local(i - 1, i, nodes_[static_cast<size_t>(i - 1)].local.inverse() * n.local);
  }
  for (const Loop& loop : loops_) {
    constraints.push_back({node_count + loop.submap, loop.node, loop.node_in_submap,
                           options_.loop_translation_sigma, options_.loop_rotation_sigma,
                           options_.loop_robust_scale});
  }
  std::vector<bool> fixed(poses.size(), false);
  fixed[static_cast<size_t>(node_count)] = true;  // the first submap holds the map frame
  const PoseGraphSummary summary = OptimizePoseGraph(constraints, fixed, options_.graph, &poses);
  if (!summary.ok) return false;
  for (int i = 0; i < node_count; ++i) nodes_[static_cast<size_t>(i)].global = poses[static_cast<size_t>(i)];
  for (size_t s = 0; s < submaps_.size(); ++s) submaps_[s].global = poses[static_cast<size_t>(node_count) + s];
  return true;
}

Rigid2d LoopClosure::NodeCorrection(size_t node) const {
  return nodes_[node].global * nodes_[node].local.inverse();
}

Rigid2d LoopClosure::CorrectionAt(double timestamp) const {
  if (nodes_.empty()) return Rigid2d();
  const auto after = std::upper_bound(nodes_.begin(), nodes_.end(), timestamp,
                                      [](double t, const Node& n) { return t < n.timestamp; });
  if (after == nodes_.begin()) return NodeCorrection(0);
  const size_t next = static_cast<size_t>(after - nodes_.begin());
  if (next == nodes_.size()) return NodeCorrection(next - 1);
  const Node& a = nodes_[next - 1];
  const Node& b = nodes_[next];
  const double span = b.timestamp - a.timestamp;
  const double t = span > 0.0 ? (timestamp - a.timestamp) / span : 0.0;
  return Interpolate(NodeCorrection(next - 1), NodeCorrection(next), t);
}

std::optional<Rigid2d> LoopClosure::SubmapInGlobal(int64_t submap_id) const {
  const auto found = submap_index_.find(submap_id);
  if (found == submap_index_.end()) return std::nullopt;
  return submaps_[static_cast<size_t>(found->second)].global;
}

}  // namespace fleetmap
