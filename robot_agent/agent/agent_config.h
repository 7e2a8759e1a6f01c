#ifndef FLEETMAP_ROBOT_AGENT_AGENT_AGENT_CONFIG_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_AGENT_CONFIG_H_

#include <map>
#include <optional>
#include <string>

#include "robot_agent/agent/uploader.h"
#include "robot_agent/detection/camera_model.h"
#include "shared/core/rigid2d.h"

namespace fleetmap {

struct SourceConfig {
  enum class Type { kCarmen, kSimulator };
  Type type = Type::kCarmen;
  // source.carmen
  std::string log_path;
  std::string camera_index;  // optional: lines "timestamp image_path" (paths relative to it)
  // source.simulator
  std::string scenario;   // a scenario file, or the name of a shipped scenario
  std::string sim_robot;  // the robot of the scenario this agent is
  bool sim_camera = false;
  // source.speed: 0 = as fast as possible, 1 = real time, k = k times real time.
  double speed = 0.0;
};

struct SlamConfig {
  std::string algorithm = "scan-matching";
  double resolution = 0.05;      // metres per cell of the submaps
  double max_range = 20.0;       // returns beyond are not used (metres)
  int submap_scans = 100;        // a submap is finished after this many inserted scans
  double submap_travel = 10.0;   // or this much travel (metres)
  double min_translation = 0.1;  // motion filter: insert a scan after this much motion
  double min_rotation = 0.087;   // radians
};

struct UploadConfig {
  UploaderOptions uploader;
  // Seconds of sensor time between trajectory revisions, and between snapshots of the submap
  // still being built (0 = only finished submaps are uploaded).
  double trajectory_period = 5.0;
  double active_submap_period = 0.0;
  // When the source ends: wait this long (wall seconds) for the outbox to drain, then exit.
  // Items left stay in the outbox for the next start. 0 = do not wait.
  double drain_timeout = 60.0;
  // On SIGINT/SIGTERM: keep uploading this long (wall seconds) before exiting.
  double flush_timeout = 5.0;
};

struct MapConfig {
  bool subscribe = true;  // follow the server's global map versions
  std::string file;       // optional: keep the latest map as FILE.pgm + FILE.yaml
  BackoffOptions reconnect;
};

// Seeing other robots: camera marker + laser fit (robot_agent/detection), one RobotDetection
// per sighting into the outbox.
struct DetectionConfig {
  bool enabled = false;
  // Where the marker colours come from (one of):
  //  - colour_model: a YAML file written by fleetmap-detect-calibrate;
  //  - marker_hues: robot id -> hue in degrees, a built-in model from the hues alone;
  //  - neither, with the simulator: learnt at start from frames the simulator renders.
  std::string colour_model;
  std::map<std::string, double> marker_hues;
  double hue_half_width = 15.0;  // degrees either side of a marker hue (marker_hues)
  double min_saturation = 0.35;  // (marker_hues)
  int learn_views = 48;          // rendered frames to learn from (simulator)
  // Camera and marker geometry. The simulator's come from its scenario; a log's from here
  // (defaults: a 640x480, 60 degree camera on the robot centre and the simulator's marker).
  CameraModel camera;
  MarkerGeometry marker;
  double laser_range_noise = 0.01;  // metres, sigma of the scanner's ranges
  // A camera frame is paired with the laser scan nearest in time, at most this far apart.
  double max_time_difference = 0.05;
  // Marker name (colour model / simulator robot) -> robot id on the server, when they differ.
  std::map<std::string, std::string> robot_ids;
  // Keep the laser returns off detected robots out of local SLAM (seen_robot_mask.h).
  bool mask_seen_robots = true;
  // Also keep out free-standing round bodies of the marker's body_radius that the laser alone
  // finds (laser_body.h) once they move: robots outside the camera's view, and with detection
  // disabled. Works with mask_seen_robots only. Off by default: it made the demo's map worse
  // (department_3robots, 88-93 -> 81-82 %) though it helped elsewhere (docs/BENCHMARKS.md).
  bool mask_laser_bodies = false;
};

// Localizing in a known map (Monte Carlo localization) instead of mapping: the robot uploads
// its poses in that map's frame and no submaps. With `share_detections`, a robot that sees
// another (detection.enabled) sends it, through the server, the density of its pose (the
// collaborative update of the paper's section IV), and applies the densities others send it.
struct LocalizationConfig {
  bool enabled = false;
  // A ROS map (YAML + image, e.g. from `fleetmapctl export`); empty = the server's global map,
  // waited for at start for at most `map_wait` seconds.
  std::string map;
  double map_wait = 120.0;
  // The robot's start in the map frame; absent = global localization (uniform belief).
  std::optional<Rigid2d> initial_pose;
  double initial_position_std = 0.3;  // metres
  double initial_heading_std = 0.1;   // radians
  int particles = 5000;               // the most the filter uses (KLD sampling uses fewer)
  int beams = 60;                     // laser returns per update
  int seed = 1;
  // After a global start, a scan-to-map search moves some particles to where the scan fits best
  // (robot_agent/localization/scan_seeding.h). It cannot tell twins apart.
  bool scan_seeding = true;
  // Augmented MCL's random injection (kidnap recovery); off by default, as in AMCL: in
  // look-alike corridors it moves the belief to the wrong one (mcl_localizer.h).
  bool random_injection = false;
  bool share_detections = true;
};

// Everything one fleetmap-agent process needs, loaded from robot.yaml.
struct AgentConfig {
  std::string robot_id;  // 1-64 characters of [A-Za-z0-9_.-]
  std::string robot_name;
  std::optional<Rigid2d> start_pose;  // local map frame in the global frame, when known
  std::string server_address = "127.0.0.1:50051";
  std::string outbox_path;
  SlamConfig slam;
  SourceConfig source;
  UploadConfig upload;
  MapConfig map;
  DetectionConfig detection;
  LocalizationConfig localization;
  double status_period = 5.0;  // seconds between status lines; 0 = none
};

// Reads and validates a configuration. Relative paths are resolved against the file's folder.
// Messages name the file and the field, e.g. "robot.yaml: slam.resolution: must be > 0, got -1".
bool LoadAgentConfig(const std::string& path, AgentConfig* config, std::string* error);
// The same from YAML text; `name` prefixes messages and `base_dir` resolves relative paths.
bool ParseAgentConfig(const std::string& yaml_text, const std::string& name,
                      const std::string& base_dir, AgentConfig* config, std::string* error);

// Checks a parsed configuration (also used after command-line overrides).
bool ValidateAgentConfig(const AgentConfig& config, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_AGENT_CONFIG_H_
