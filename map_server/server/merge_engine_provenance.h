#ifndef FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_PROVENANCE_H_
#define FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_PROVENANCE_H_

#include <map>
#include <string>
#include <vector>

#include "map_server/merge/merge_engine.h"
#include "map_server/store/records.h"

namespace fleetmap {

// What the merge engine has said about one robot so far: how it was placed, or why not yet.
struct RobotMergeStatus {
  std::string accepted_source;  // "detection", "matching"; empty while not aligned by evidence
  std::string accepted_note;
  std::string hypothesis_note;  // the latest plausible alignment waiting for confirmation
  std::string rejection_note;   // the latest evidence that failed a gate
};

// Short names used in placements and provenance keys.
const char* EvidenceName(EvidenceKind kind);

// Records each event under the robots it concerns.
void NoteEvents(const std::vector<AlignmentEvent>& events,
                std::map<std::string, RobotMergeStatus>* status);

// Every registered robot's placement as the engine currently has it. Pure.
std::vector<RobotPlacementRecord> MakePlacements(
    const std::map<std::string, RobotRecord>& robots, const MergeEngine& engine,
    const std::map<std::string, RobotMergeStatus>& status);

// Adds the engine's events and quality figures to a version's provenance: counts per event
// type, one block of keys per accepted alignment and hypothesis
// ("alignment.<i>.<type>.<evidence>.<robot_a>.<robot_b>.score" ...), the map consistency and
// graph residual figures, and a readable trigger line when an alignment was accepted.
void AddEngineProvenance(const std::vector<AlignmentEvent>& events, const MergeQuality& quality,
                         VersionRecord* info);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_MERGE_ENGINE_PROVENANCE_H_
