// MergeEngine: joins on matches alone held on probation before they are published.
//
// A join on matches alone is judged again once its part's map has grown by join_review_growth
// (merge_engine_join_review.cc), and withdrawn when the grown maps explain it as well elsewhere;
// but every version until then showed the wrong join (session 43: five pairs wrong for 5-35 s,
// none at the end; department_3robots' robot3 fits the south corridor turned round over 92 % of
// its map until it has driven on). So such a join is first judged at that growth before it is
// made: an alignment passing every gate on matches alone is noted, and accepted when it passes
// them again once both parts together hold match_join_probation_growth times the finished
// submaps they held when it first passed. A detection agreeing ends the wait at once (Consider).
// The cost is that true joins come later: building_4robots' robots meet at the end of the run,
// and held there, none was placed. So once uploads settle (HoldMatchOnlyJoins(false)), what is
// held is judged on the maps as they are, as a rebuild from everything stored would judge it.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

bool MergeEngine::ProbationApplies(const Hypothesis& h) const {
  return !h.detection && hold_match_only_joins_ && options_.match_join_probation_growth > 1.0;
}

bool MergeEngine::HeldOnProbation(Hypothesis* h, const std::vector<RelativeEdge>& confirmed_by,
                                  MergeUpdate* update) {
  if (!ProbationApplies(*h)) return false;
  const int submaps = FinishedSubmaps(Root(h->robot_a)) + FinishedSubmaps(Root(h->robot_b));
  auto on_probation = std::find_if(probation_.begin(), probation_.end(),
                                   [&](const Hypothesis& p) { return SameAlignment(*h, p); });
  if (on_probation == probation_.end()) {
    on_probation = probation_.insert(probation_.end(), *h);
    on_probation->probation_from = submaps;
    on_probation->confirmed_by = confirmed_by;
  } else if (submaps >= options_.match_join_probation_growth * on_probation->probation_from) {
    h->event.reason += "; passed again after probation, from " +
                       std::to_string(on_probation->probation_from) + " to " +
                       std::to_string(submaps) + " finished submaps";
    probation_.erase(on_probation);
    return false;
  }
  const int until = static_cast<int>(
      std::ceil(options_.match_join_probation_growth * on_probation->probation_from));
  AlignmentEvent event = h->event;
  event.type = AlignmentEventType::kHypothesis;
  event.reason += "; passes on matches alone: on probation until both maps hold " +
                  std::to_string(until) + " finished submaps (" + std::to_string(submaps) +
                  " now), then judged again";
  update->events.push_back(event);
  return true;
}

bool MergeEngine::ProbationRunning(const Hypothesis& h) const {
  if (!ProbationApplies(h)) return false;
  const int submaps = FinishedSubmaps(Root(h.robot_a)) + FinishedSubmaps(Root(h.robot_b));
  return std::any_of(probation_.begin(), probation_.end(), [&](const Hypothesis& p) {
    return submaps < options_.match_join_probation_growth * p.probation_from && SameAlignment(h, p);
  });
}

void MergeEngine::JudgeHeldAlignments(MergeUpdate* update) {
  if (hold_match_only_joins_ || probation_.empty()) return;
  const std::vector<Hypothesis> held = std::move(probation_);
  probation_.clear();
  for (Hypothesis h : held) {
    if (Root(h.robot_a) == Root(h.robot_b)) continue;
    h.event.reason +=
        "; on probation from " + std::to_string(h.probation_from) +
        " finished submaps, judged again on the maps as they are once uploads settled";
    // The provenance says why a join held to the end is not made.
    const auto refuse = [&](const std::string& why) {
      AlignmentEvent event = h.event;
      event.type = AlignmentEventType::kRejected;
      event.reason += ": " + why;
      update->events.push_back(event);
    };
    // Detections received since may contradict it, as Consider asks of a new match.
    const DetectionVotes votes = DetectionsAbout(h);
    if (votes.contradicting >= options_.min_contradicting_detections &&
        votes.contradicting > votes.agreeing) {
      refuse(std::to_string(votes.contradicting) + " detection(s) contradict it");
      continue;
    }
    // The evidence that confirmed it stands; the whole maps may have changed since.
    const WholeMapVerdict whole =
        WholeMapAmbiguity(Root(h.robot_a), Root(h.robot_b), FrameTransform(h), MaxRefuted(h));
    if (whole.ambiguity) {
      refuse(*whole.ambiguity);
      continue;
    }
    // Said once: the maps often read as they did when it was held.
    if (!whole.note.empty() && h.event.reason.find(whole.note) == std::string::npos) {
      h.event.reason += " (" + whole.note + ")";
    }
    Accept(h, h.confirmed_by, update);
  }
}

}  // namespace fleetmap
