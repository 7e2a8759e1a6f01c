// The true alignment's twins under the maps' symmetries, judged as the whole-map check judges
// an alternative (merge_engine_ambiguity.cc), with both maps free of drift.

#include "map_server/bench/merge_sim_twins.h"

#include <algorithm>
#include <utility>

#include "map_server/merge/map_symmetries.h"

namespace fleetmap {

std::vector<std::optional<PairTwin>> PairTwins(
    const std::vector<std::unique_ptr<MatchTarget>>& targets,
    const std::vector<MatchSource>& sources, const MatchTarget& all, const MatchSource& all_source,
    const MergeEngineOptions& options) {
  // As the engine finds a part's symmetries (MergeEngine::SearchWholeMaps), without excusing
  // walls on the robots' trails: the truth has no drift to excuse.
  const MapSymmetryOptions symmetry = WholeMapSymmetryOptions(options);
  std::vector<std::vector<Rigid2d>> moves;  // each map's own
  for (size_t i = 0; i < targets.size(); ++i) {
    moves.push_back(targets[i]->empty()
                        ? std::vector<Rigid2d>{}
                        : MapSymmetries(*targets[i], sources[i], sources[i].fine, symmetry));
  }
  const std::vector<Rigid2d> all_moves =
      all.empty() ? std::vector<Rigid2d>{}
                  : MapSymmetries(all, all_source, all_source.fine, symmetry);
  std::vector<std::optional<PairTwin>> twins;
  for (size_t a = 0; a < targets.size(); ++a) {
    for (size_t b = a + 1; b < targets.size(); ++b) {
      std::optional<PairTwin>& best = twins.emplace_back();
      if (targets[a]->empty() || targets[b]->empty()) continue;
      const MatchTarget& target = *targets[a];
      const auto crossings = [&](const Rigid2d& b_moved) {
        return target.ContradictionsAt(sources[b].fine, b_moved) +
               targets[b]->ContradictionsAt(sources[a].fine, b_moved.inverse());
      };
      const MatchResult at_truth = target.Evaluate(sources[b], Rigid2d(), options.cross_gates);
      if (!(at_truth.score > 0.0)) continue;
      const int truth_crossings = crossings(Rigid2d());
      Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
      for (const Eigen::Vector2d& p : sources[b].fine) centroid += p;
      centroid /= static_cast<double>(std::max<size_t>(1, sources[b].fine.size()));
      // b moved by a's symmetry lands where a looks as it does at b's true place; b moved by
      // its own, where b looks as it does there; by the maps' together, where they look as
      // there. Each way round.
      std::vector<Rigid2d> candidates;
      for (const std::vector<Rigid2d>* owner :
           {&std::as_const(moves[a]), &std::as_const(moves[b]), &all_moves}) {
        for (const Rigid2d& m : *owner) {
          candidates.push_back(m);
          candidates.push_back(m.inverse());
        }
      }
      for (const Rigid2d& candidate : candidates) {
        const Rigid2d pose = target.BestFitNear(sources[b], candidate, options.cross_gates);
        const MatchResult at_twin = target.Evaluate(sources[b], pose, options.cross_gates);
        PairTwin twin;
        twin.move = pose;
        twin.shift = (pose * centroid - centroid).norm();
        twin.score_ratio = at_twin.score / at_truth.score;
        twin.overlap_share = at_twin.overlap / std::max(at_truth.overlap, 1e-9);
        twin.overlap_score_ratio = at_twin.overlap_score / std::max(at_truth.overlap_score, 1e-9);
        // As the whole-map check's alternatives compete: explaining nearly as much over all
        // points, or as consistent where the maps overlap over a sizeable share of the truth's
        // overlap. (The engine lets a twin it finds from a symmetry compete whatever it scores;
        // counting only those that would also compete as alternatives, a twin listed is one any
        // rule on the maps has to weigh.)
        const bool competes = twin.score_ratio >= options.whole_map_ambiguity ||
                              (twin.overlap_share >= options.whole_map_min_overlap &&
                               twin.overlap_score_ratio >= options.whole_map_ambiguity);
        if (!competes) continue;
        twin.crossings = crossings(pose);
        twin.truth_crossings = truth_crossings;
        twin.ruled_out =
            options.whole_map_min_contradictions > 0 &&
            truth_crossings <= options.whole_map_max_join_contradictions &&
            twin.crossings >=
                std::min(1.0, twin.overlap_share) * options.whole_map_min_contradictions +
                    options.whole_map_contradiction_ratio * truth_crossings;
        // The one least ruled out: standing first, then the fewest crossings.
        if (!best || (best->ruled_out && !twin.ruled_out) ||
            (best->ruled_out == twin.ruled_out && twin.crossings < best->crossings)) {
          best = twin;
        }
      }
    }
  }
  return twins;
}

}  // namespace fleetmap
