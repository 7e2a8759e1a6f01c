#include "map_server/bench/engine_flags.h"

namespace fleetmap {

void AddEngineFlags(CLI::App* app, MergeEngineOptions* options) {
  app->add_option(
         "--odometry-sigma-per-metre", options->odometry_translation_sigma_per_metre,
         "merge engine: translation sigma of consecutive-submap edges per metre between them")
      ->capture_default_str();
  app->add_option("--odometry-rotation-sigma-per-metre", options->odometry_rotation_sigma_per_metre,
                  "merge engine: rotation sigma (rad) of consecutive-submap edges per metre")
      ->capture_default_str();
  app->add_option("--match-translation-sigma", options->match_translation_sigma,
                  "merge engine: translation sigma (m) of cross-robot match edges")
      ->capture_default_str();
  app->add_option("--match-rotation-sigma", options->match_rotation_sigma,
                  "merge engine: rotation sigma (rad) of cross-robot match edges")
      ->capture_default_str();
  app->add_option("--odometry-translation-sigma", options->odometry_translation_sigma,
                  "merge engine: translation sigma (m) of consecutive-submap edges")
      ->capture_default_str();
  app->add_option("--odometry-rotation-sigma", options->odometry_rotation_sigma,
                  "merge engine: rotation sigma (rad) of consecutive-submap edges")
      ->capture_default_str();
  app->add_option("--whole-map-contradiction-window", options->whole_map_contradiction_window,
                  "merge engine: wall points in seen-free space are counted with each tile of a "
                  "map moved on its own up to this far (MergeEngineOptions::"
                  "whole_map_contradiction_window; 0: rigid)")
      ->capture_default_str();
  app->add_option("--whole-map-contradiction-window-per-metre",
                  options->whole_map_contradiction_window_per_metre,
                  "merge engine: a tile moves at most this far per metre of its distance from "
                  "the map's centroid (MergeEngineOptions::"
                  "whole_map_contradiction_window_per_metre)")
      ->capture_default_str();
  app->add_option("--whole-map-contradiction-tile", options->whole_map_contradiction_tile,
                  "merge engine: the tiles' side, metres (MergeEngineOptions::"
                  "whole_map_contradiction_tile)")
      ->capture_default_str();
  app->add_option("--whole-map-ambiguity", options->whole_map_ambiguity,
                  "merge engine: a join on matches alone waits while another alignment of the "
                  "whole maps scores this share of it (MergeEngineOptions::whole_map_ambiguity; 0: "
                  "no check)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--whole-map-min-overlap", options->whole_map_min_overlap,
                  "merge engine: an alternative alignment of the whole maps that scores less also "
                  "keeps a join on matches alone waiting when it lands this share of the join's "
                  "overlap and is as consistent there (MergeEngineOptions::whole_map_min_overlap)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--whole-map-min-contradictions", options->whole_map_min_contradictions,
                  "merge engine: an alternative alignment of the whole maps stops blocking a join "
                  "when their walls cross seen-free space there at this many points plus 4 times "
                  "the join's, and a join that puts this many there itself waits "
                  "(MergeEngineOptions::whole_map_min_contradictions; 0: never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-max-join-contradictions", options->whole_map_max_join_contradictions,
                  "merge engine: only a join whose own walls cross seen-free space at this many "
                  "points or fewer may rule alternatives out by theirs "
                  "(MergeEngineOptions::whole_map_max_join_contradictions)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-max-examined", options->whole_map_max_examined,
                  "merge engine: most alternative alignments of the whole maps examined for one "
                  "join, best scoring first (MergeEngineOptions::whole_map_max_examined)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-unseen-score", options->whole_map_unseen_score,
                  "merge engine: what a wall point landing where the other map saw nothing scores "
                  "in the search for alternative alignments of the whole maps "
                  "(MergeEngineOptions::whole_map_unseen_score; 0: no such search)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--whole-map-max-refuted", options->whole_map_max_refuted,
                  "merge engine: most alternatives the walls may rule out for one join before it "
                  "waits (MergeEngineOptions::whole_map_max_refuted)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-rule-out-higher", options->whole_map_rule_out_higher,
                  "merge engine: the walls also rule out alternatives scoring more than the join, "
                  "counted with their tiles fitted (MergeEngineOptions::whole_map_rule_out_higher)")
      ->capture_default_str();
  app->add_flag("!--no-whole-map-matches", options->whole_map_matches,
                "merge engine: do not match parts' whole maps when no submap places them "
                "(MergeEngineOptions::whole_map_matches)");
  app->add_option("--whole-map-match-max-refuted", options->whole_map_match_max_refuted,
                  "merge engine: the same as --whole-map-max-refuted for a join on the whole maps "
                  "matched (MergeEngineOptions::whole_map_match_max_refuted)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--join-review-growth", options->join_review_growth,
                  "merge engine: a join on matches alone is judged again over the grown maps each "
                  "time its component grows by this factor, and withdrawn when ambiguous then "
                  "(MergeEngineOptions::join_review_growth; 0: never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_flag("!--no-submap-match-join-review", options->review_submap_match_joins,
                "merge engine: judge again only joins on the whole maps, not those on submap "
                "matches (MergeEngineOptions::review_submap_match_joins)");
  app->add_option("--match-join-probation", options->match_join_probation_growth,
                  "merge engine: a join on matches alone waits unpublished until both maps have "
                  "grown by this factor, and is made if it passes again then "
                  "(MergeEngineOptions::match_join_probation_growth; 0: made at once)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-symmetries", options->whole_map_symmetry_max_examined,
                  "merge engine: a join on matches alone also waits on its twins under moves that "
                  "fit either map onto itself; this many such moves are looked for, best first "
                  "(MergeEngineOptions::whole_map_symmetry_max_examined; 0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-symmetry-min-overlap", options->whole_map_symmetry_min_overlap,
                  "merge engine: a move fits a map onto itself when it lands this share of the map "
                  "on itself (MergeEngineOptions::whole_map_symmetry_min_overlap)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--whole-map-symmetry-max-contradictions",
                  options->whole_map_symmetry_max_contradictions,
                  "merge engine: a move that puts this many of a map's walls in space the map saw "
                  "free does not fit it onto itself "
                  "(MergeEngineOptions::whole_map_symmetry_max_contradictions)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--max-pull-distance", options->match.refine.max_pull_distance,
                  "merge engine: metres; in a match's refinement, points farther than this from "
                  "a wall do not pull (PoseRefinerOptions::max_pull_distance; 0: no limit)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--edge-refine-window", options->edge_refine_window,
                  "merge engine: metres; each match edge is refined again against the one submap "
                  "it is tied to, moving at most this far (MergeEngineOptions::edge_refine_window; "
                  "0: not refined)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--search-threads", options->search_threads,
                  "merge engine: threads for an update's searches that do not depend on each "
                  "other; the results are the same for any count "
                  "(MergeEngineOptions::search_threads; 0: one per core, at most an "
                  "update's nearby searches)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--odometry-robust-scale", options->odometry_robust_scale,
                  "merge engine: Cauchy scale, in sigmas, of consecutive-submap edges (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--whole-map-body-radius", options->whole_map_body_radius,
                  "merge engine: metres; blobs of wall wholly this close to where a robot drove "
                  "are its body, not walls seen through, in the whole-map check "
                  "(MergeEngineOptions::whole_map_body_radius; 0: counted as walls)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--cross-retry-growth", options->cross_retry_growth,
                  "merge engine: a submap not yet joined is searched over another component's map "
                  "again once that map holds this many times as many finished submaps "
                  "(MergeEngineOptions::cross_retry_growth; 0: once)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app->add_option("--loop-min-id-gap", options->loop_min_id_gap,
                  "merge engine: loop closures match a new submap against its robot's own submaps "
                  "at least this many ids older (MergeEngineOptions::loop_min_id_gap)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app->add_option("--loop-translation-sigma", options->loop_translation_sigma,
                  "merge engine: translation sigma (m) of loop-closure edges within one robot")
      ->capture_default_str();
  app->add_option("--loop-rotation-sigma", options->loop_rotation_sigma,
                  "merge engine: rotation sigma (rad) of loop-closure edges within one robot")
      ->capture_default_str();
}

}  // namespace fleetmap
