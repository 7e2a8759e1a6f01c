#include "map_server/bench/merge_sim_diagnosis.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "map_server/merge/match_target.h"
#include "map_server/merge/pose_graph.h"

namespace fleetmap {
namespace {

bool IsMatch(const RelativeEdge& e) {
  return e.kind == EdgeKind::kCrossMatch || e.kind == EdgeKind::kDetectionMatch;
}

// How far a submap's walls stand from the world's, its anchor placed true: the least-squares
// shift along the walls' normals (each wall point's distance to the true wall, found by a ray
// along its normal; points with no side or no true wall within 0.15 m are left out). Nothing
// with fewer than 20 points.
std::optional<Eigen::Vector2d> ContentShift(const Submap& submap, const Rigid2d& true_anchor,
                                            const MergeEngineOptions& options,
                                            const sim::World& world) {
  constexpr double kReach = 0.3;  // metres in front of the wall the ray starts
  const MatchSource source = MakeMatchSource(submap.grid, Rigid2d(), options.match);
  Eigen::Matrix2d normal_scatter = Eigen::Matrix2d::Zero();
  Eigen::Vector2d weighted_offsets = Eigen::Vector2d::Zero();
  int used = 0;
  for (size_t i = 0; i < source.fine.size(); ++i) {
    if (source.fine_normals[i].squaredNorm() < 0.5) continue;
    const Eigen::Vector2d n = true_anchor.rotation_matrix() * source.fine_normals[i];
    const Eigen::Vector2d start = true_anchor * source.fine[i] + kReach * n;
    const sim::RayHit hit = world.CastRay(start, std::atan2(-n.y(), -n.x()), 2.0 * kReach);
    const double offset = kReach - hit.distance;  // > 0: the map's wall stands into free space
    if (!hit.hit || std::abs(offset) > 0.15) continue;
    normal_scatter += n * n.transpose();
    weighted_offsets += n * offset;
    ++used;
  }
  if (used < 20) return std::nullopt;
  return normal_scatter.ldlt().solve(weighted_offsets);
}

void PrintAnchors(const MergeEngine& engine, const std::map<NodeId, Submap>& submaps,
                  const RunTruth& known, const MergeEngineOptions& options, const sim::World& world,
                  const std::optional<Rigid2d>& global_in_world) {
  const std::map<NodeId, Rigid2d> poses = engine.SubmapPoses();
  std::optional<std::pair<NodeId, Rigid2d>> previous;
  for (const auto& [id, submap] : submaps) {
    const auto truth = TrueAnchor(known, id);
    const size_t i = static_cast<size_t>(
        std::find(known.names.begin(), known.names.end(), id.robot) - known.names.begin());
    if (!truth || i >= known.names.size() || !known.local_in_world[i]) continue;
    std::string step = "-";
    if (previous && previous->first.robot == id.robot) {
      const Submap& before = submaps.at(previous->first);
      step = PoseError(before.submap_in_local.inverse() * submap.submap_in_local,
                       previous->second.inverse() * *truth);
    }
    const auto merged = poses.find(id);
    const auto shift = ContentShift(submap, *truth, options, world);
    char content[64] = "-";
    if (shift) std::snprintf(content, sizeof(content), "(%6.3f %6.3f) m", shift->x(), shift->y());
    std::printf("    %s/%lld: local %s, step %s, merged %s, walls off the world's by %s\n",
                id.robot.c_str(), static_cast<long long>(id.submap),
                PoseError(*known.local_in_world[i] * submap.submap_in_local, *truth).c_str(),
                step.c_str(),
                merged == poses.end() || !global_in_world
                    ? "-"
                    : PoseError(*global_in_world * merged->second, *truth).c_str(),
                content);
    previous = std::make_pair(id, *truth);
  }
}

// The measured position minus where the true anchors and local SLAM's poses within them put
// the seen robot, in the observer's frame (x ahead), averaged per ordered pair.
void PrintDetectionErrors(const MergeEngine& engine, const RunTruth& known) {
  std::map<std::pair<std::string, std::string>, std::vector<Eigen::Vector2d>> errors;
  for (const DetectionEdge& e : engine.graph().detections()) {
    const auto observer = TrueAnchor(known, e.observer), observed = TrueAnchor(known, e.observed);
    if (!observer || !observed) continue;
    const Eigen::Vector2d predicted = (*observer * e.observer_robot_in_node).inverse() *
                                      (*observed * e.observed_robot_in_node).translation();
    errors[{e.observer.robot, e.observed.robot}].push_back(e.position - predicted);
  }
  for (const auto& [pair, list] : errors) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const Eigen::Vector2d& d : list) mean += d / static_cast<double>(list.size());
    std::printf("    detections %s -> %s: %zu, mean error %.3f m ahead, %.3f m left\n",
                pair.first.c_str(), pair.second.c_str(), list.size(), mean.x(), mean.y());
  }
}

// The engine's graph with the chosen edges set to the true relations, and without its
// detection edges when `detections` is false (then held by the reference robot's first node).
PoseGraph GraphWithTruth(const PoseGraph& merged, const RunTruth& known, bool true_matches,
                         bool true_chains, bool detections, const std::string& reference,
                         bool chain_headings_only = false) {
  PoseGraph graph = merged;
  if (!detections) {
    graph = PoseGraph();
    for (const auto& [id, pose] : merged.nodes()) graph.SetNode(id, pose);
    for (const RelativeEdge& e : merged.edges()) graph.AddEdge(e);
    // The reference robot's first node holds the frame (nodes are ordered by robot, then id).
    const auto first = merged.nodes().lower_bound(NodeId{reference, INT64_MIN});
    if (first != merged.nodes().end() && first->first.robot == reference)
      graph.SetFixed(first->first);
  }
  for (size_t i = 0; i < graph.edges().size(); ++i) {
    RelativeEdge e = graph.edges()[i];
    const auto from = TrueAnchor(known, e.from), to = TrueAnchor(known, e.to);
    const bool set = IsMatch(e) ? true_matches : e.kind == EdgeKind::kOdometry && true_chains;
    if (!set || !from || !to) continue;
    const Rigid2d truth = from->inverse() * *to;
    e.to_in_from = IsMatch(e) || !chain_headings_only
                       ? truth
                       : Rigid2d(e.to_in_from.translation(), truth.rotation());
    graph.UpdateEdge(i, e);
  }
  if (true_matches || true_chains || !detections) graph.Solve();
  return graph;
}

void PrintErrorBudget(const MergeEngine& engine, const RunTruth& known) {
  struct Variant {
    const char* name;
    bool true_matches, true_chains, detections;
    bool chain_headings_only = false;
  };
  const Variant variants[] = {
      {"as merged", false, false, true},
      {"match edges at the truth", true, false, true},
      {"consecutive-submap edges at the truth", false, true, true},
      {"consecutive-submap edges' headings at the truth", false, true, true, true},
      {"match and consecutive-submap edges at the truth", true, true, true},
      {"without detection edges", false, false, false},
      {"without detection edges, consecutive-submap edges at the truth", false, true, false},
  };
  for (const Variant& v : variants) {
    const PoseGraph graph =
        GraphWithTruth(engine.graph(), known, v.true_matches, v.true_chains, v.detections,
                       engine.reference_robot(), v.chain_headings_only);
    std::printf("    first submaps' pairs, %s:", v.name);
    for (size_t a = 0; a < known.names.size(); ++a) {
      for (size_t b = a + 1; b < known.names.size(); ++b) {
        const NodeId first_a{known.names[a], 0}, first_b{known.names[b], 0};
        const auto pa = graph.NodePose(first_a), pb = graph.NodePose(first_b);
        const auto ta = TrueAnchor(known, first_a), tb = TrueAnchor(known, first_b);
        if (!pa || !pb || !ta || !tb) continue;
        std::printf(" %s-%s %s;", known.names[a].c_str(), known.names[b].c_str(),
                    PoseError(pa->inverse() * *pb, ta->inverse() * *tb).c_str());
      }
    }
    std::printf("\n");
  }
}

// Where the `to` submap fits best on the `from` submap alone within `linear` / `angular` of
// `centre` (only its points landing where `from` saw anything, as the engine refines its match
// edges), and the mean distance of the matched points to the walls at each of `poses`, then at
// that fit.
struct LocalFit {
  Rigid2d pose;
  std::string residuals;
};
LocalFit FitWithin(const OccupancyGrid& from, const OccupancyGrid& to, const Rigid2d& centre,
                   double linear, double angular, const std::vector<Rigid2d>& poses,
                   const MergeEngineOptions& options) {
  const MatchTarget target(from, options.match);
  MatchSource source = MakeMatchSource(to, Rigid2d(), options.match);
  KeepPointsSeenBy(from, centre, &source);
  SearchWindow window;
  window.center = centre;
  window.linear_half_extent = Eigen::Vector2d::Constant(linear);
  window.angular_half_extent = angular;
  MatchGates gates = WithoutMinimums(options.verify_gates);
  gates.judge_overlap_only = true;
  const MatchResult fit = target.Match(source, window, gates);
  LocalFit result{fit.pose, "residual"};
  char text[32];
  for (const Rigid2d& pose : poses) {
    std::snprintf(text, sizeof(text), " %.4f /", target.Evaluate(source, pose, gates).residual);
    result.residuals += text;
  }
  std::snprintf(text, sizeof(text), " %.4f m", fit.residual);
  result.residuals += text;
  return result;
}

// A match edge: where its two submaps fit best within 0.3 m / 0.02 rad of the truth, and the
// residuals at the edge's measurement, at the truth and at that fit.
std::string FitNearTruth(const OccupancyGrid& from, const OccupancyGrid& to, const Rigid2d& truth,
                         const Rigid2d& measured, const MergeEngineOptions& options) {
  const LocalFit fit = FitWithin(from, to, truth, 0.3, 0.02, {measured, truth}, options);
  return "best fit near the truth " + PoseError(fit.pose, truth) + "; " + fit.residuals;
}

// A consecutive-submap edge: where its two submaps fit best within 0.1 m / 0.01 rad of local
// SLAM's relation, and the residuals at the truth and at that fit. Could the merge's own
// matching measure the edge better than local SLAM did?
std::string ChainFit(const OccupancyGrid& from, const OccupancyGrid& to, const Rigid2d& truth,
                     const Rigid2d& chain, const MergeEngineOptions& options) {
  const LocalFit fit = FitWithin(from, to, chain, 0.1, 0.01, {truth}, options);
  return "the two submaps' own fit " + PoseError(fit.pose, truth) + "; " + fit.residuals;
}

void PrintEdges(const MergeEngine& engine, const std::map<NodeId, Submap>& submaps,
                const RunTruth& known, const MergeEngineOptions& options) {
  for (const RelativeEdge& e : engine.graph().edges()) {
    const auto from = TrueAnchor(known, e.from), to = TrueAnchor(known, e.to);
    if (!from || !to) continue;
    const Rigid2d truth = from->inverse() * *to;
    std::string fit;
    if (e.kind == EdgeKind::kOdometry && submaps.count(e.from) && submaps.count(e.to)) {
      fit = "; " +
            ChainFit(submaps.at(e.from).grid, submaps.at(e.to).grid, truth, e.to_in_from, options);
    }
    if (IsMatch(e) && submaps.count(e.from) && submaps.count(e.to)) {
      fit = "; " + FitNearTruth(submaps.at(e.from).grid, submaps.at(e.to).grid, truth, e.to_in_from,
                                options);
    }
    std::printf("    edge %s %s/%lld -> %s/%lld: %s%s\n", EdgeKindName(e.kind),
                e.from.robot.c_str(), static_cast<long long>(e.from.submap), e.to.robot.c_str(),
                static_cast<long long>(e.to.submap), PoseError(e.to_in_from, truth).c_str(),
                fit.c_str());
  }
}

}  // namespace

void PrintSubmapDiagnosis(const MergeEngine& engine, const std::map<NodeId, Submap>& submaps,
                          const RunTruth& known, const MergeEngineOptions& options,
                          const sim::World& world) {
  const auto ref = std::find(known.names.begin(), known.names.end(), engine.reference_robot());
  if (ref == known.names.end()) return;
  const auto& global_in_world =
      known.local_in_world[static_cast<size_t>(ref - known.names.begin())];
  PrintAnchors(engine, submaps, known, options, world, global_in_world);
  PrintDetectionErrors(engine, known);
  PrintErrorBudget(engine, known);
  PrintEdges(engine, submaps, known, options);
}

}  // namespace fleetmap
