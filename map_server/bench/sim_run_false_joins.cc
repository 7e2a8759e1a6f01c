// SimRun: the pairs the merge as fed places wrong as the run goes, and its events as they come.

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "map_server/bench/sim_run.h"

namespace fleetmap {

void SimRun::NoteFalseJoins() {
  const std::vector<std::optional<Rigid2d>> errors = PairErrors(engine_, truth_);
  for (size_t k = 0; k < errors.size(); ++k) {
    const bool wrong =
        errors[k] && IsFalseMerge(*errors[k], options_.false_translation, options_.false_rotation);
    const auto it = false_as_fed_.find(k);
    if (wrong && it == false_as_fed_.end()) {
      false_as_fed_.emplace(k, FalseJoin{result_->sim_seconds, *errors[k], std::nullopt});
    } else if (wrong) {
      it->second.until.reset();
    } else if (it != false_as_fed_.end() && !it->second.until) {
      it->second.until = result_->sim_seconds;
    }
  }
}

std::string SimRun::FalseJoinsLine() const {
  std::string line = "  false joins as the run went: " + std::to_string(false_as_fed_.size());
  size_t k = 0;
  for (size_t a = 0; a < n_; ++a) {
    for (size_t b = a + 1; b < n_; ++b, ++k) {
      const auto it = false_as_fed_.find(k);
      if (it == false_as_fed_.end()) continue;
      const FalseJoin& f = it->second;
      char until[40] = "to the end";
      if (f.until) std::snprintf(until, sizeof(until), "until t=%.0f s", *f.until);
      char text[200];
      std::snprintf(text, sizeof(text), "; %s-%s from t=%.0f s %s (%.2f m, %.1f deg off)",
                    infos_[a].name.c_str(), infos_[b].name.c_str(), f.from, until,
                    f.off.translation().norm(),
                    std::abs(NormalizeAngle(f.off.rotation())) * 180.0 / M_PI);
      line += text;
    }
  }
  return line;
}

void SimRun::PrintEvents(const MergeUpdate& update) const {
  if (!options_.verbose) return;
  for (const AlignmentEvent& e : update.events) {
    // How far the evidence's estimate is from the truth (start frames; includes drift).
    std::string truth_error;
    const auto a = index_.find(e.robot_a), b = index_.find(e.robot_b);
    if (e.local_b_in_local_a && a != index_.end() && b != index_.end() &&
        truth_.local_in_world[a->second] && truth_.local_in_world[b->second]) {
      const Rigid2d diff =
          (truth_.local_in_world[a->second]->inverse() * *truth_.local_in_world[b->second])
              .inverse() *
          *e.local_b_in_local_a;
      char text[80];
      std::snprintf(text, sizeof(text), " [vs truth %.2f m, %.2f deg]", diff.translation().norm(),
                    std::abs(NormalizeAngle(diff.rotation())) * 180.0 / M_PI);
      truth_error = text;
    }
    std::printf("    t=%.0f %s %s/%s score %.3f amb %.3f overlap %.3f%s: %s\n",
                result_->sim_seconds, AlignmentEventTypeName(e.type), e.robot_a.c_str(),
                e.robot_b.c_str(), e.score, e.ambiguity, e.overlap, truth_error.c_str(),
                e.reason.c_str());
  }
}

}  // namespace fleetmap
