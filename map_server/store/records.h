#ifndef FLEETMAP_MAP_SERVER_STORE_RECORDS_H_
#define FLEETMAP_MAP_SERVER_STORE_RECORDS_H_

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "shared/codec/grid_codec.h"
#include "shared/core/rigid2d.h"
#include "shared/core/robot_detection.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

// What the server stores, in plain types (no protobuf, no SQLite).

struct RobotRecord {
  std::string robot_id;
  std::string name;
  std::string sensor_description;
  std::string algorithm;
  double registered_unix_time = 0.0;
  // The robot's local map frame in the global frame, when given at registration.
  std::optional<Rigid2d> local_in_global;
  // Localizes in a known map instead of mapping (RegisterRobotRequest.localization_only).
  bool localization_only = false;
};

struct SubmapKey {
  std::string robot_id;
  int64_t submap_id = 0;
  int64_t revision = 0;
  bool operator==(const SubmapKey& o) const {
    return robot_id == o.robot_id && submap_id == o.submap_id && revision == o.revision;
  }
  bool operator<(const SubmapKey& o) const {
    if (robot_id != o.robot_id) return robot_id < o.robot_id;
    if (submap_id != o.submap_id) return submap_id < o.submap_id;
    return revision < o.revision;
  }
};

struct StoredSubmap {
  int64_t seq = 0;  // ingest order, grows by one per accepted revision
  double received_unix_time = 0.0;
  Submap submap;
};

struct TrajectoryRecord {
  std::string robot_id;
  int64_t revision = 0;
  double received_unix_time = 0.0;
  Trajectory poses;  // robot in its local map frame
};

struct DetectionRecord {
  int64_t seq = 0;  // ingest order
  int64_t detection_id = 0;
  double received_unix_time = 0.0;
  RobotDetection detection;
};

struct RobotPlacementRecord {
  std::string robot_id;
  bool placed = false;
  Rigid2d local_in_global;
  // Where the robot's local frame sits as its first submap places it: where the robot started.
  // local_in_global follows the newest submap, so it also carries the local SLAM drift since.
  // Only when placed; absent in versions stored before it was recorded (schema version 1).
  std::optional<Rigid2d> start_in_global;
  std::string source;  // "registration", "unplaced", later "detection", "matching"
  std::string note;
};

struct DetectionRef {
  std::string observer_id;
  int64_t detection_id = 0;
};

// One global map version's metadata and provenance.
struct VersionRecord {
  int64_t version = 0;  // assigned by the store
  double created_unix_time = 0.0;
  int64_t covered_submap_seq = 0;  // every submap with seq <= this is folded in
  std::string trigger;
  std::vector<std::string> trigger_robot_ids;
  std::vector<SubmapKey> new_submaps;
  std::vector<DetectionRef> new_detections;
  std::map<std::string, double> quality;
  std::string merge_engine;
  std::vector<RobotPlacementRecord> placements;
  GridGeometry geometry;
  bool grid_available = false;
};

// The outcome of an idempotent put.
enum class PutOutcome {
  kInserted,
  kDuplicate,     // the natural key was stored before; nothing changed
  kOutOfOrder,    // older than the newest stored revision
  kUnknownRobot,  // the robot is not registered
  kError,         // storage failure (message in the error string)
};

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_RECORDS_H_
