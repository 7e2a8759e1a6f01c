#include "map_server/bench/merge_sim_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace fleetmap {

void PrintRun(const RunResult& result, double wall) {
  for (const auto& line : result.lines) std::cout << line << "\n";
  std::printf(
      "  nearby submaps of different robots (true anchors within %.0f m): %d pairs, median "
      "%.3f m / %.3f deg, max %.3f m / %.3f deg, %d beyond the false-merge thresholds\n",
      kNearSubmaps, result.near_pairs, result.near_median_translation,
      result.near_median_rotation * 180.0 / M_PI, result.near_max_translation,
      result.near_max_rotation * 180.0 / M_PI, result.near_pairs_off);
  std::printf(
      "  merged pairs %d/%d, false merges %d, max error %.3f m / %.3f deg, map within 1 "
      "cell of a wall %.2f %% (best rigid fit %.2f %%), submaps %d, Update() median %.1f ms (max "
      "%.1f), per new "
      "submap median %.1f ms, sim %.0f s, wall %.0f s, masked returns %lld, laser bodies %lld "
      "(%lld within 0.3 m of another robot)\n",
      result.placed_pairs, result.pairs, result.false_merges, result.max_translation,
      result.max_rotation * 180.0 / M_PI, 100.0 * result.map_accuracy,
      100.0 * result.map_accuracy_best_fit, result.submaps, result.median_update_ms,
      result.max_update_ms, result.median_fold_ms, result.sim_seconds, wall,
      static_cast<long long>(result.masked_returns), static_cast<long long>(result.laser_bodies),
      static_cast<long long>(result.laser_bodies_on_robots));
  std::printf(
      "  map bounds: submaps at their true anchors %.2f %%; each robot's own map, "
      "start placed true:",
      100.0 * result.map_at_true_anchors);
  for (double m : result.map_local_per_robot) std::printf(" %.2f %%", 100.0 * m);
  std::printf("\n");
  int overlapping = 0, overlapping_placed = 0;
  std::printf("  pair overlaps (share of the smaller map, at the true anchors):");
  for (size_t k = 0; k < result.pair_overlap.size(); ++k) {
    const bool placed = k < result.pair_placed.size() && result.pair_placed[k];
    std::printf(" %.0f %%%s", 100.0 * result.pair_overlap[k], placed ? "" : " (not merged)");
    if (result.pair_overlap[k] >= kMinPairOverlap) {
      ++overlapping;
      overlapping_placed += placed;
    }
  }
  std::printf("; at least %.0f %%: %d pairs, %d merged\n", 100.0 * kMinPairOverlap, overlapping,
              overlapping_placed);
  std::printf("  pair wall points in seen-free space (at the true anchors):");
  for (int crossings : result.pair_crossings) std::printf(" %d", crossings);
  std::printf("\n");
  if (!result.pair_twins.empty()) {
    std::printf("  pair twins (the maps' symmetries, at the true anchors):");
    for (size_t k = 0; k < result.pair_twins.size(); ++k) {
      const std::optional<PairTwin>& twin = result.pair_twins[k];
      std::printf("%s", k == 0 ? " " : "; ");
      if (!twin) {
        std::printf("none");
        continue;
      }
      std::printf(
          "centroid %.1f m / %.0f deg off, score %.2f of the truth's (overlap %.2f of the "
          "truth's, %.2f of its score there), walls in seen-free space %d against %d: %s",
          twin->shift, std::abs(NormalizeAngle(twin->move.rotation())) * 180.0 / M_PI,
          twin->score_ratio, twin->overlap_share, twin->overlap_score_ratio, twin->crossings,
          twin->truth_crossings, twin->ruled_out ? "ruled out" : "stands");
    }
    std::printf("\n");
  }
  std::fflush(stdout);
}

std::string DetectionsMode(bool detections, double outlier_fraction) {
  if (!detections) return "no detections";
  if (outlier_fraction <= 0.0) return "with detections";
  char corrupted[64];
  std::snprintf(corrupted, sizeof(corrupted), "with detections, %g %% corrupted",
                100.0 * outlier_fraction);
  return corrupted;
}

void PrintSummary(const std::string& name, const std::string& mode,
                  const std::vector<RunResult>& runs) {
  if (runs.size() < 2) return;
  double map_sum = 0.0, map_min = 1.0, map_max = 0.0, worst_pair = 0.0, fit_sum = 0.0;
  int merged = 0, pairs = 0, false_merges = 0, overlapping = 0, overlapping_placed = 0;
  int false_as_fed = 0;
  for (const RunResult& r : runs) {
    false_as_fed += r.false_merges_as_fed;
    map_sum += r.map_accuracy;
    fit_sum += r.map_accuracy_best_fit;
    map_min = std::min(map_min, r.map_accuracy);
    map_max = std::max(map_max, r.map_accuracy);
    worst_pair = std::max(worst_pair, r.max_translation);
    merged += r.placed_pairs;
    pairs += r.pairs;
    false_merges += r.false_merges;
    for (size_t k = 0; k < r.pair_overlap.size(); ++k) {
      if (r.pair_overlap[k] < kMinPairOverlap) continue;
      ++overlapping;
      overlapping_placed += k < r.pair_placed.size() && r.pair_placed[k];
    }
  }
  const double n = static_cast<double>(runs.size());
  std::printf(
      "  SUMMARY %s (%s), %zu seeds: map %.2f %% mean (%.2f-%.2f; best rigid fit %.2f %% "
      "mean), worst pair %.3f m, merged pairs %d/%d (overlapping by %.0f %% or more: %d/%d), "
      "false merges %d (as the run went: %d)\n",
      name.c_str(), mode.c_str(), runs.size(), 100.0 * map_sum / n, 100.0 * map_min,
      100.0 * map_max, 100.0 * fit_sum / n, worst_pair, merged, pairs, 100.0 * kMinPairOverlap,
      overlapping_placed, overlapping, false_merges, false_as_fed);
  std::fflush(stdout);
}

}  // namespace fleetmap
