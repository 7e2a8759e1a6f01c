#include "map_server/bench/merge_sim_scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>

#include "map_server/merge/log_odds_canvas.h"
#include "map_server/merge/match_target.h"
#include "map_server/merge/merge_engine.h"
#include "robot_agent/sim/map_accuracy.h"

namespace fleetmap {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::optional<Rigid2d> TrueAnchor(const RunTruth& known, const NodeId& id) {
  const auto anchor = known.anchors.find(id);
  const auto robot = std::find(known.names.begin(), known.names.end(), id.robot);
  if (anchor == known.anchors.end() || robot == known.names.end()) return std::nullopt;
  const auto& truth = known.at_scan[static_cast<size_t>(robot - known.names.begin())];
  const auto t = truth.find(anchor->second.second);
  if (t == truth.end()) return std::nullopt;
  return t->second * anchor->second.first;
}

std::string PoseError(const Rigid2d& estimate, const Rigid2d& truth) {
  const Rigid2d diff = truth.inverse() * estimate;
  char text[96];
  std::snprintf(text, sizeof(text), "%.3f m (%6.3f %6.3f) %6.3f deg", diff.translation().norm(),
                diff.translation().x(), diff.translation().y(),
                NormalizeAngle(diff.rotation()) * 180.0 / M_PI);
  return text;
}

std::string HeadingErrorSummary(const Trajectory& trajectory, const RunTruth& known, size_t robot) {
  if (robot >= known.at_scan.size() || !known.local_in_world[robot]) return "";
  struct Sample {
    double time, error;
    Eigen::Vector2d position;
  };
  std::vector<Sample> samples;
  for (const StampedPose& p : trajectory) {
    const auto truth = known.at_scan[robot].find(p.timestamp);
    if (truth == known.at_scan[robot].end()) continue;
    const Rigid2d estimate = *known.local_in_world[robot] * p.pose;
    samples.push_back({p.timestamp, NormalizeAngle(estimate.rotation() - truth->second.rotation()),
                       truth->second.translation()});
  }
  if (samples.empty()) return "";
  double sum_squares = 0.0, largest = 0.0, largest_step = 0.0;
  const Sample* step_at = &samples.front();
  size_t earlier = 0;  // the first sample within a second before the current one
  for (const Sample& s : samples) {
    sum_squares += s.error * s.error;
    largest = std::max(largest, std::abs(s.error));
    while (samples[earlier].time < s.time - 1.0) ++earlier;
    const double step = std::abs(s.error - samples[earlier].error);
    if (step > largest_step) {
      largest_step = step;
      step_at = &s;
    }
  }
  char text[220];
  std::snprintf(text, sizeof(text),
                "  %s local SLAM heading error: rms %.3f deg, max %.3f deg; largest change within "
                "1 s %.3f deg at %.0f s (%.1f, %.1f)",
                known.names[robot].c_str(), std::sqrt(sum_squares / samples.size()) * 180.0 / M_PI,
                largest * 180.0 / M_PI, largest_step * 180.0 / M_PI, step_at->time,
                step_at->position.x(), step_at->position.y());
  return text;
}

namespace {

// The lattice cells (kOverlapResolution) of the world a canvas has seen.
std::set<std::pair<int, int>> SeenCells(const LogOddsCanvas& canvas) {
  std::set<std::pair<int, int>> seen;
  for (int y = 0; y < canvas.height(); ++y) {
    for (int x = 0; x < canvas.width(); ++x) {
      const int i = canvas.min_cell().x() + x, j = canvas.min_cell().y() + y;
      if (canvas.Sum(i, j) != 0.0f) seen.emplace(i, j);
    }
  }
  return seen;
}

void PairOverlaps(const std::map<NodeId, Submap>& submaps, const RunTruth& known, bool with_twins,
                  RunResult* result) {
  std::vector<LogOddsCanvas> at_truth(known.names.size(), LogOddsCanvas(kOverlapResolution));
  for (const auto& [id, submap] : submaps) {
    const auto truth = TrueAnchor(known, id);
    const auto robot = std::find(known.names.begin(), known.names.end(), id.robot);
    if (truth && robot != known.names.end()) {
      at_truth[static_cast<size_t>(robot - known.names.begin())].AddSubmap(submap.grid, *truth,
                                                                           1.0f);
    }
  }
  std::vector<std::set<std::pair<int, int>>> seen;
  for (const LogOddsCanvas& canvas : at_truth) seen.push_back(SeenCells(canvas));
  // The whole-map check's view of each map (MergeEngine::SearchWholeMaps): its lattice, its
  // score grid, its thinned wall points.
  const MergeEngineOptions defaults;
  OccupancyGridOptions grid_options = defaults.render_grid;
  grid_options.resolution = kOverlapResolution;
  MatchTargetOptions match_options = defaults.match;
  match_options.grid.resolution = kOverlapResolution;
  match_options.grid.sigma = 0.0;
  std::vector<std::unique_ptr<MatchTarget>> targets;
  std::vector<MatchSource> sources;
  for (const LogOddsCanvas& canvas : at_truth) {
    const OccupancyGrid grid = canvas.ToGrid(grid_options);
    targets.push_back(std::make_unique<MatchTarget>(grid, match_options));
    sources.push_back(MakeMatchSource(grid, Rigid2d(), match_options));
  }
  result->pair_overlap.clear();
  result->pair_crossings.clear();
  for (size_t a = 0; a < seen.size(); ++a) {
    for (size_t b = a + 1; b < seen.size(); ++b) {
      size_t both = 0;
      for (const auto& cell : seen[a]) both += seen[b].count(cell);
      const size_t smaller = std::min(seen[a].size(), seen[b].size());
      result->pair_overlap.push_back(smaller == 0 ? 0.0 : static_cast<double>(both) / smaller);
      const bool empty = targets[a]->empty() || targets[b]->empty();
      result->pair_crossings.push_back(
          empty ? 0
                : targets[a]->ContradictionsAt(sources[b].fine, Rigid2d()) +
                      targets[b]->ContradictionsAt(sources[a].fine, Rigid2d()));
    }
  }
  result->pair_twins.clear();
  if (with_twins) {
    LogOddsCanvas all(kOverlapResolution);
    for (const auto& [id, submap] : submaps) {
      if (const auto truth = TrueAnchor(known, id)) all.AddSubmap(submap.grid, *truth, 1.0f);
    }
    const OccupancyGrid grid = all.ToGrid(grid_options);
    const MatchTarget all_target(grid, match_options);
    result->pair_twins = PairTwins(targets, sources, all_target,
                                   MakeMatchSource(grid, Rigid2d(), match_options), defaults);
  }
}

}  // namespace

void ScoreMapBounds(const std::map<NodeId, Submap>& submaps, const RunTruth& known,
                    const sim::World& world, RunResult* result, bool with_twins) {
  const MergeEngineOptions defaults;
  LogOddsCanvas at_truth(defaults.render_resolution);
  std::vector<LogOddsCanvas> local(known.names.size(), LogOddsCanvas(defaults.render_resolution));
  for (const auto& [id, submap] : submaps) {
    const auto truth = TrueAnchor(known, id);
    if (truth) at_truth.AddSubmap(submap.grid, *truth, 1.0f);
    const auto robot = std::find(known.names.begin(), known.names.end(), id.robot);
    const size_t i = static_cast<size_t>(robot - known.names.begin());
    if (robot != known.names.end() && known.local_in_world[i]) {
      local[i].AddSubmap(submap.grid, *known.local_in_world[i] * submap.submap_in_local, 1.0f);
    }
  }
  PairOverlaps(submaps, known, with_twins, result);
  const WallMask walls = sim::WorldWalls(world);
  const auto score = [&](const LogOddsCanvas& canvas) {
    if (canvas.empty()) return 0.0;
    return ScoreOnWalls(canvas.ToGrid(defaults.render_grid), Rigid2d(), walls).fraction();
  };
  result->map_at_true_anchors = score(at_truth);
  result->map_local_per_robot.clear();
  for (const LogOddsCanvas& canvas : local) result->map_local_per_robot.push_back(score(canvas));
}

std::vector<std::optional<Rigid2d>> PairErrors(const MergeEngine& engine, const RunTruth& known) {
  // A start frame is placed where the merged graph put the robot's first submap:
  // RobotToGlobal() frames the robot by its latest submap, so it also carries the local SLAM
  // drift since the start.
  const std::map<NodeId, Rigid2d> poses = engine.SubmapPoses();
  const auto start_in_global = [&](size_t i) -> std::optional<Rigid2d> {
    const auto it = poses.find(NodeId{known.names[i], 0});
    if (it == poses.end() || !known.first_submap_in_local[i] || !known.local_in_world[i] ||
        !engine.RobotToGlobal(known.names[i])) {
      return std::nullopt;
    }
    return it->second * known.first_submap_in_local[i]->inverse();
  };
  std::vector<std::optional<Rigid2d>> errors;
  for (size_t a = 0; a < known.names.size(); ++a) {
    for (size_t b = a + 1; b < known.names.size(); ++b) {
      const auto ga = start_in_global(a);
      const auto gb = start_in_global(b);
      if (!ga || !gb) {
        errors.push_back(std::nullopt);
        continue;
      }
      const Rigid2d truth = known.local_in_world[a]->inverse() * *known.local_in_world[b];
      errors.push_back(truth.inverse() * (ga->inverse() * *gb));
    }
  }
  return errors;
}

bool IsFalseMerge(const Rigid2d& error, double false_translation, double false_rotation) {
  return error.translation().norm() > false_translation ||
         std::abs(NormalizeAngle(error.rotation())) > false_rotation;
}

void ScoreMerge(const MergeEngine& engine, const RunTruth& known, const sim::World& world,
                double false_translation, double false_rotation, RunResult* result,
                std::string* error) {
  // Relative transforms between every pair of robots' start frames against the truth; the
  // latest submaps' frames are printed for reference.
  const std::vector<std::optional<Rigid2d>> errors = PairErrors(engine, known);
  size_t k = 0;
  for (size_t a = 0; a < known.names.size(); ++a) {
    for (size_t b = a + 1; b < known.names.size(); ++b, ++k) {
      ++result->pairs;
      char line[256];
      if (!errors[k]) {
        std::snprintf(line, sizeof(line), "  %s-%s: not merged", known.names[a].c_str(),
                      known.names[b].c_str());
        result->lines.push_back(line);
        result->pair_placed.push_back(false);
        continue;
      }
      ++result->placed_pairs;
      result->pair_placed.push_back(true);
      const Rigid2d& diff = *errors[k];
      const double t = diff.translation().norm();
      const double r = std::abs(NormalizeAngle(diff.rotation()));
      if (IsFalseMerge(diff, false_translation, false_rotation)) ++result->false_merges;
      result->max_translation = std::max(result->max_translation, t);
      result->max_rotation = std::max(result->max_rotation, r);
      const Rigid2d truth = known.local_in_world[a]->inverse() * *known.local_in_world[b];
      const Rigid2d latest = truth.inverse() * (engine.RobotToGlobal(known.names[a])->inverse() *
                                                *engine.RobotToGlobal(known.names[b]));
      std::snprintf(line, sizeof(line),
                    "  %s-%s: %.3f m, %.3f deg (latest submaps' frames: %.3f m, %.3f deg)",
                    known.names[a].c_str(), known.names[b].c_str(), t, r * 180.0 / M_PI,
                    latest.translation().norm(),
                    std::abs(NormalizeAngle(latest.rotation())) * 180.0 / M_PI);
      result->lines.push_back(line);
    }
  }
  // Local consistency: nearby submaps of different robots.
  const std::map<NodeId, Rigid2d> poses = engine.SubmapPoses();
  std::vector<std::pair<NodeId, Rigid2d>>
      true_anchors;  // placed submaps' true anchors in the world
  for (const auto& [id, pose] : poses) {
    if (const auto truth = TrueAnchor(known, id)) true_anchors.emplace_back(id, *truth);
  }
  std::vector<double> near_t, near_r;
  for (size_t i = 0; i < true_anchors.size(); ++i) {
    for (size_t j = i + 1; j < true_anchors.size(); ++j) {
      const auto& [id_i, true_i] = true_anchors[i];
      const auto& [id_j, true_j] = true_anchors[j];
      if (id_i.robot == id_j.robot ||
          (true_i.translation() - true_j.translation()).norm() > kNearSubmaps)
        continue;
      const Rigid2d diff =
          (true_i.inverse() * true_j).inverse() * (poses.at(id_i).inverse() * poses.at(id_j));
      near_t.push_back(diff.translation().norm());
      near_r.push_back(std::abs(NormalizeAngle(diff.rotation())));
      result->near_pairs_off += IsFalseMerge(diff, false_translation, false_rotation);
    }
  }
  result->near_pairs = static_cast<int>(near_t.size());
  if (!near_t.empty()) {
    result->near_median_translation = Median(near_t);
    result->near_max_translation = *std::max_element(near_t.begin(), near_t.end());
    result->near_median_rotation = Median(near_r);
    result->near_max_rotation = *std::max_element(near_r.begin(), near_r.end());
  }
  const std::string& reference = engine.reference_robot();
  for (size_t i = 0; i < known.names.size(); ++i) {
    if (known.names[i] != reference || !known.local_in_world[i]) continue;
    const auto grid = engine.RenderGlobalMap(std::nullopt, 0.05, error);
    if (!grid) continue;
    const WallMask walls = sim::WorldWalls(world);
    result->map_accuracy = ScoreOnWalls(*grid, *known.local_in_world[i], walls).fraction();
    result->map_accuracy_best_fit =
        ScoreOnWallsBestFit(*grid, *known.local_in_world[i], walls).fraction();
  }
}

}  // namespace fleetmap
