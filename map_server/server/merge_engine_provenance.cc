#include "map_server/server/merge_engine_provenance.h"

#include <cmath>
#include <cstdio>

#include "map_server/server/merge_worker.h"

namespace fleetmap {
namespace {

std::string Figures(const AlignmentEvent& e) {
  char text[160];
  std::snprintf(text, sizeof(text), "score %.3f, ambiguity %.3f, overlap %.3f, residual %.3f m",
                e.score, e.ambiguity, e.overlap, e.residual);
  return text;
}

std::string Describe(const AlignmentEvent& e) {
  return std::string(AlignmentEventTypeName(e.type)) + " (" + EvidenceName(e.evidence) + " " +
         e.robot_a + " / " + e.robot_b + ": " + Figures(e) + (e.reason.empty() ? "" : "; ") +
         e.reason + ")";
}

const char* TypeKey(AlignmentEventType type) {
  switch (type) {
    case AlignmentEventType::kAlignmentAccepted: return "accepted";
    case AlignmentEventType::kHypothesis: return "hypothesis";
    case AlignmentEventType::kRejected: return "rejected";
    case AlignmentEventType::kConstraintAdded: return "constraint";
    case AlignmentEventType::kPending: return "pending";
    case AlignmentEventType::kWithdrawn: return "withdrawn";
  }
  return "unknown";
}

}  // namespace

const char* EvidenceName(EvidenceKind kind) {
  switch (kind) {
    case EvidenceKind::kDetection: return "detection";
    case EvidenceKind::kCrossMatch: return "matching";
    case EvidenceKind::kLoopClosure: return "loop-closure";
  }
  return "unknown";
}

void NoteEvents(const std::vector<AlignmentEvent>& events,
                std::map<std::string, RobotMergeStatus>* status) {
  for (const AlignmentEvent& e : events) {
    for (const std::string* robot : {&e.robot_a, &e.robot_b}) {
      if (robot->empty()) continue;
      RobotMergeStatus& s = (*status)[*robot];
      switch (e.type) {
        case AlignmentEventType::kAlignmentAccepted:
          if (s.accepted_source.empty()) {
            s.accepted_source = EvidenceName(e.evidence);
            s.accepted_note = Describe(e);
          }
          break;
        case AlignmentEventType::kHypothesis: s.hypothesis_note = Describe(e); break;
        case AlignmentEventType::kRejected: s.rejection_note = Describe(e); break;
        case AlignmentEventType::kWithdrawn:
          if (*robot == e.robot_b) {  // the robot split off is unplaced until evidence agrees again
            s.accepted_source.clear();
            s.accepted_note.clear();
            s.rejection_note = Describe(e);
          }
          break;
        default: break;
      }
    }
  }
}

std::vector<RobotPlacementRecord> MakePlacements(
    const std::map<std::string, RobotRecord>& robots, const MergeEngine& engine,
    const std::map<std::string, RobotMergeStatus>& status) {
  std::vector<RobotPlacementRecord> placements;
  for (const auto& [id, robot] : robots) {
    RobotPlacementRecord p;
    p.robot_id = id;
    const auto it = status.find(id);
    const RobotMergeStatus none;
    const RobotMergeStatus& s = it == status.end() ? none : it->second;
    if (robot.localization_only) {
      p = LocalizationPlacement(robot);
    } else if (const std::optional<Rigid2d> local_in_global = engine.RobotToGlobal(id)) {
      p.placed = true;
      p.local_in_global = *local_in_global;
      p.start_in_global = engine.RobotStartToGlobal(id);
      if (robot.local_in_global) {
        p.source = "registration";
      } else if (id == engine.reference_robot()) {
        p.source = "reference";
        p.note = "defines the global frame (the first robot to send a submap)";
      } else if (!s.accepted_source.empty()) {
        p.source = s.accepted_source;
        p.note = s.accepted_note;
      } else {
        p.source = "matching";
        p.note = "joined through another robot's alignment";
      }
    } else {
      p.source = "unplaced";
      if (!s.hypothesis_note.empty()) {
        p.note = "waiting for a second piece of evidence: " + s.hypothesis_note;
      } else if (!s.rejection_note.empty()) {
        p.note = "no alignment passed the gates yet; latest: " + s.rejection_note;
      } else {
        p.note = "no alignment yet (no detection or cross-robot submap match so far)";
      }
    }
    placements.push_back(std::move(p));
  }
  return placements;
}

void AddEngineProvenance(const std::vector<AlignmentEvent>& events, const MergeQuality& quality,
                         VersionRecord* info) {
  std::map<std::string, double>& q = info->quality;
  int index = 0;
  std::string accepted, withdrawn;
  for (const AlignmentEvent& e : events) {
    q[std::string("events_") + TypeKey(e.type)] += 1.0;
    if (e.type == AlignmentEventType::kWithdrawn) {
      withdrawn += (withdrawn.empty() ? "" : "; ") + e.robot_b + " split from " + e.robot_a + " (" + e.reason + ")";
    }
    if (e.type == AlignmentEventType::kRejected) {
      double& best = q["rejected_best_score"];
      best = std::max(best, e.score);
    }
    if (e.type != AlignmentEventType::kAlignmentAccepted &&
        e.type != AlignmentEventType::kHypothesis) {
      continue;
    }
    // Bounded, so a long batch cannot bloat one version's metadata.
    if (index >= 32) continue;
    const std::string key = "alignment." + std::to_string(index++) + "." + TypeKey(e.type) + "." +
                            EvidenceName(e.evidence) + "." + e.robot_a + "." + e.robot_b + ".";
    q[key + "score"] = e.score;
    q[key + "ambiguity"] = e.ambiguity;
    q[key + "overlap"] = e.overlap;
    q[key + "residual_m"] = e.residual;
    if (e.local_b_in_local_a) {
      q[key + "x"] = e.local_b_in_local_a->translation().x();
      q[key + "y"] = e.local_b_in_local_a->translation().y();
      q[key + "theta"] = e.local_b_in_local_a->rotation();
    }
    if (e.type == AlignmentEventType::kAlignmentAccepted) {
      accepted += (accepted.empty() ? "" : "; ") + e.robot_b + " aligned with " + e.robot_a +
                  " by " + EvidenceName(e.evidence) + " (" + Figures(e) + ")";
    }
  }
  q["inter_robot_edges"] = quality.inter_robot_edges;
  q["inter_robot_rms_translation_m"] = quality.inter_robot_rms_translation;
  q["inter_robot_max_translation_m"] = quality.inter_robot_max_translation;
  q["inter_robot_rms_rotation_rad"] = quality.inter_robot_rms_rotation;
  q["overlapping_cells"] = static_cast<double>(quality.overlapping_cells);
  q["disagreeing_cells"] = static_cast<double>(quality.disagreeing_cells);
  q["disagreement_fraction"] = quality.disagreement_fraction();
  if (!withdrawn.empty()) info->trigger = "alignment withdrawn: " + withdrawn;
  if (!accepted.empty()) {
    info->trigger = (withdrawn.empty() ? "" : info->trigger + "; ") + "alignment accepted: " + accepted;
  }
}

}  // namespace fleetmap
