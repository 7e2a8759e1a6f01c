#include "map_server/bench/merge_sim_scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "robot_agent/sim/map_accuracy.h"

namespace fleetmap {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void ScoreMerge(const MergeEngine& engine, const RunTruth& known, const sim::World& world,
                double false_translation, double false_rotation, RunResult* result,
                std::string* error) {
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < known.names.size(); ++i) index[known.names[i]] = i;
  // Relative transforms between every pair of robots' start frames against the truth. A start
  // frame is placed where the merged graph put the robot's first submap: RobotToGlobal() frames
  // the robot by its latest submap, so it also carries the local SLAM drift since the start
  // (printed for reference).
  const std::map<NodeId, Rigid2d> poses = engine.SubmapPoses();
  const auto start_in_global = [&](size_t i) -> std::optional<Rigid2d> {
    const auto it = poses.find(NodeId{known.names[i], 0});
    if (it == poses.end() || !known.first_submap_in_local[i]) return std::nullopt;
    return it->second * known.first_submap_in_local[i]->inverse();
  };
  for (size_t a = 0; a < known.names.size(); ++a) {
    for (size_t b = a + 1; b < known.names.size(); ++b) {
      ++result->pairs;
      const auto ga = start_in_global(a);
      const auto gb = start_in_global(b);
      const auto la = engine.RobotToGlobal(known.names[a]);
      const auto lb = engine.RobotToGlobal(known.names[b]);
      char line[256];
      if (!ga || !gb || !la || !lb || !known.local_in_world[a] || !known.local_in_world[b]) {
        std::snprintf(line, sizeof(line), "  %s-%s: not merged", known.names[a].c_str(),
                      known.names[b].c_str());
        result->lines.push_back(line);
        continue;
      }
      ++result->placed_pairs;
      const Rigid2d estimated = ga->inverse() * *gb;
      const Rigid2d truth = known.local_in_world[a]->inverse() * *known.local_in_world[b];
      const Rigid2d diff = truth.inverse() * estimated;
      const double t = diff.translation().norm();
      const double r = std::abs(NormalizeAngle(diff.rotation()));
      if (t > false_translation || r > false_rotation) ++result->false_merges;
      result->max_translation = std::max(result->max_translation, t);
      result->max_rotation = std::max(result->max_rotation, r);
      const Rigid2d latest = truth.inverse() * (la->inverse() * *lb);
      std::snprintf(line, sizeof(line),
                    "  %s-%s: %.3f m, %.3f deg (latest submaps' frames: %.3f m, %.3f deg)",
                    known.names[a].c_str(), known.names[b].c_str(), t, r * 180.0 / M_PI,
                    latest.translation().norm(),
                    std::abs(NormalizeAngle(latest.rotation())) * 180.0 / M_PI);
      result->lines.push_back(line);
    }
  }
  // Local consistency: nearby submaps of different robots.
  std::vector<std::pair<NodeId, Rigid2d>>
      true_anchors;  // placed submaps' true anchors in the world
  for (const auto& [id, pose] : poses) {
    const auto anchor = known.anchors.find(id);
    if (anchor == known.anchors.end()) continue;
    const auto& truth = known.at_scan[index.at(id.robot)];
    const auto t = truth.find(anchor->second.second);
    if (t == truth.end()) continue;
    true_anchors.emplace_back(id, t->second * anchor->second.first);
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
      result->near_pairs_off += near_t.back() > false_translation || near_r.back() > false_rotation;
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
    if (grid)
      result->map_accuracy =
          sim::ScoreAgainstWalls(*grid, *known.local_in_world[i], world).fraction();
  }
}

}  // namespace fleetmap
