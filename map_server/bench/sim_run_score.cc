// SimRun: uploads settled (held joins judged, the merge rebuilt as the server does), then scored.

#include <algorithm>
#include <cstdio>
#include <string>

#include "map_server/bench/merge_sim_diagnosis.h"
#include "map_server/bench/sim_run.h"

namespace fleetmap {

void SimRun::RebuildAsSettled(MergeEngine* rebuilt) const {
  // Submaps in arrival order, then the trajectories and the detections, then Update() until
  // nothing is postponed. All at once, as the server's rebuild does: no probation.
  rebuilt->HoldMatchOnlyJoins(false);
  for (const NodeId& id : arrival_) rebuilt->AddOrUpdateSubmap(latest_submaps_.at(id));
  for (size_t i = 0; i < n_; ++i) rebuilt->SetTrajectory(infos_[i].name, slams_[i]->trajectory());
  for (const RobotDetection& d : all_detections_) rebuilt->AddDetection(d);
  for (int i = 0; i == 0 || (i < 10000 && rebuilt->HasPendingWork()); ++i) rebuilt->Update();
}

void SimRun::SettleAsFed() {
  // As the server's worker does once uploads settle: joins held on probation judged now.
  const size_t placed = engine_.PlacedRobots().size();
  engine_.HoldMatchOnlyJoins(false);
  for (int i = 0; i < 1000 && engine_.HasPendingWork(); ++i) {
    PrintEvents(engine_.Update());
    NoteFalseJoins();
  }
  char line[160];
  std::snprintf(line, sizeof(line),
                "  uploads settled: the engine as fed placed %zu robots, %zu once what it held on "
                "probation was judged",
                placed, engine_.PlacedRobots().size());
  result_->lines.push_back(line);
}

bool SimRun::Score(std::string* error) {
  MergeEngine rebuilt(options_.engine);
  if (options_.settled_rebuild) {
    SettleAsFed();
    RebuildAsSettled(&rebuilt);
  }
  // The server keeps the rebuild only when it places at least as many robots.
  const bool rebuild_kept =
      options_.settled_rebuild && rebuilt.PlacedRobots().size() >= engine_.PlacedRobots().size();
  const sim::World& world = sim_->world();
  if (options_.settled_rebuild) {
    char line[200];
    std::snprintf(line, sizeof(line),
                  "  settled rebuild: %zu robots placed (the engine fed as the run went: %zu): %s",
                  rebuilt.PlacedRobots().size(), engine_.PlacedRobots().size(),
                  rebuild_kept ? "kept" : "not kept");
    result_->lines.push_back(line);
    // Both merges against the truth and by the engine's own consistency figure: whether the
    // engine could tell which of the two is better.
    RunResult as_fed, whole;
    std::string ignored;
    ScoreMerge(engine_, truth_, world, options_.false_translation, options_.false_rotation, &as_fed,
               &ignored);
    ScoreMerge(rebuilt, truth_, world, options_.false_translation, options_.false_rotation, &whole,
               &ignored);
    std::snprintf(
        line, sizeof(line),
        "  as fed: map %.2f %%, disagreement %.5f; rebuilt: map %.2f %%, disagreement %.5f",
        100.0 * as_fed.map_accuracy, engine_.Quality().disagreement_fraction(),
        100.0 * whole.map_accuracy, rebuilt.Quality().disagreement_fraction());
    result_->lines.push_back(line);
  }
  result_->false_merges_as_fed = static_cast<int>(false_as_fed_.size());
  result_->lines.push_back(FalseJoinsLine());
  const MergeEngine& scored = rebuild_kept ? rebuilt : engine_;
  ScoreMerge(scored, truth_, world, options_.false_translation, options_.false_rotation, result_,
             error);
  ScoreMapBounds(latest_submaps_, truth_, world, result_, options_.twins);
  if (options_.diagnose)
    PrintSubmapDiagnosis(scored, latest_submaps_, truth_, options_.engine, world);
  result_->median_update_ms = Median(update_ms_);
  result_->max_update_ms =
      update_ms_.empty() ? 0.0 : *std::max_element(update_ms_.begin(), update_ms_.end());
  result_->median_fold_ms = Median(fold_ms_);
  return true;
}

}  // namespace fleetmap
