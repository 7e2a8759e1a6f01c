#include "map_server/bench/merge_replay_inputs.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <memory>
#include <set>

#include "map_server/store/sqlite_map_store.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {
namespace {

constexpr double kTimeTolerance = 1e-3;  // seconds between a scan time and its truth tick

// The truth trajectory keyed by time, for the nearest-tick lookups below.
bool ReadPoses(const std::string& path, std::map<double, Rigid2d>* poses, std::string* error) {
  Trajectory trajectory;
  if (!ReadTrajectory(path, &trajectory, error)) return false;
  for (const StampedPose& p : trajectory) (*poses)[p.timestamp] = p.pose;
  return true;
}

}  // namespace

bool ReadStore(const std::string& path, StoreContents* out, std::string* error) {
  // Open() creates a missing database: a typo must not score an empty run.
  if (!std::filesystem::is_regular_file(path)) {
    *error = path + ": no such database file";
    return false;
  }
  SqliteMapStoreOptions options;
  options.path = path;
  std::unique_ptr<SqliteMapStore> store = SqliteMapStore::Open(options, error);
  if (!store) return false;
  out->robots = store->ListRobots();
  out->submaps = store->LatestSubmaps("");
  std::sort(out->submaps.begin(), out->submaps.end(),
            [](const StoredSubmap& a, const StoredSubmap& b) { return a.seq < b.seq; });
  for (const RobotRecord& robot : out->robots) {
    const auto trajectory = store->LatestTrajectory(robot.robot_id);
    if (trajectory) out->trajectories[robot.robot_id] = trajectory->poses;
  }
  out->detections = store->DetectionsAfter(0);
  out->latest_version = store->LatestVersion();
  if (out->latest_version) out->latest_grid = store->GetVersionGrid(out->latest_version->version);
  return true;
}

bool ReadTruthFiles(const std::string& dir, TruthFiles* truth, std::string* error) {
  const std::string manifest_path = dir + "/manifest.yaml";
  if (!std::filesystem::is_regular_file(manifest_path)) {
    *error = manifest_path + ": no simulator manifest in the truth folder";
    return false;
  }
  try {
    const YAML::Node manifest = YAML::LoadFile(manifest_path);
    for (const YAML::Node& robot : manifest["robots"]) {
      truth->names.push_back(robot["name"].as<std::string>());
      truth->poses.emplace_back();
      const std::string file = dir + "/" + robot["ground_truth"].as<std::string>();
      if (!ReadPoses(file, &truth->poses.back(), error)) return false;
    }
    // The world file beside the plain map keeps the world's metadata.
    std::string world = dir + "/" + manifest["world_map"].as<std::string>();
    const std::string with_metadata = world.substr(0, world.size() - 5) + ".world.yaml";
    truth->world_path = std::filesystem::exists(with_metadata) ? with_metadata : world;
  } catch (const YAML::Exception& e) {
    *error = manifest_path + ": " + e.what();
    return false;
  }
  return true;
}

std::optional<Rigid2d> NearestPose(const std::map<double, Rigid2d>& poses, double time) {
  auto it = poses.lower_bound(time - kTimeTolerance);
  if (it == poses.end() || it->first > time + kTimeTolerance) return std::nullopt;
  const auto next = std::next(it);
  if (next != poses.end() && std::abs(next->first - time) < std::abs(it->first - time)) it = next;
  return it->second;
}

bool BuildRunTruth(const StoreContents& store, const TruthFiles& files, RunTruth* truth,
                   int* unmatched, std::string* error) {
  const size_t n = files.names.size();
  truth->names = files.names;
  truth->local_in_world.assign(n, std::nullopt);
  truth->first_submap_in_local.assign(n, std::nullopt);
  truth->at_scan.assign(n, {});
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < n; ++i) index[files.names[i]] = i;
  for (const RobotRecord& robot : store.robots) {
    if (!index.count(robot.robot_id)) {
      *error = "robot '" + robot.robot_id + "' of the database is not in the truth's manifest";
      return false;
    }
  }
  std::vector<std::optional<double>> first_scan(n);
  std::set<std::pair<size_t, double>> missing;
  for (const StoredSubmap& stored : store.submaps) {
    const Submap& submap = stored.submap;
    const auto robot = index.find(submap.robot_id);
    if (robot == index.end()) {
      *error = "submap of robot '" + submap.robot_id + "' not in the truth's manifest";
      return false;
    }
    const size_t i = robot->second;
    if (submap.submap_id == 0) truth->first_submap_in_local[i] = submap.submap_in_local;
    if (submap.scan_poses.empty()) continue;
    truth->anchors[NodeId{submap.robot_id, submap.submap_id}] = {
        submap.scan_poses.front().pose.inverse() * submap.submap_in_local,
        submap.scan_poses.front().timestamp};
    for (const StampedPose& scan : submap.scan_poses) {
      if (!first_scan[i] || scan.timestamp < *first_scan[i]) first_scan[i] = scan.timestamp;
      const auto pose = NearestPose(files.poses[i], scan.timestamp);
      if (pose) {
        truth->at_scan[i][scan.timestamp] = *pose;
      } else {
        missing.insert({i, scan.timestamp});
      }
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if (!first_scan[i]) continue;
    const auto start = truth->at_scan[i].find(*first_scan[i]);
    if (start != truth->at_scan[i].end()) truth->local_in_world[i] = start->second;
  }
  *unmatched = static_cast<int>(missing.size());
  return true;
}

}  // namespace fleetmap
