#include "robot_agent/detection/tools/sim_dataset.h"

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "shared/io/carmen_reader.h"

namespace fleetmap {
namespace {

namespace fs = std::filesystem;

bool ReadCameraIndex(const std::string& path, std::vector<SimCameraFrame>* frames,
                     std::string* error) {
  std::ifstream file(path);
  if (!file) {
    *error = path + ": cannot open camera index";
    return false;
  }
  const fs::path base = fs::path(path).parent_path();
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    SimCameraFrame frame;
    std::string name;
    double mount_x, mount_y, mount_z, mount_yaw;
    CameraModel& c = frame.camera;
    if (!(in >> frame.timestamp >> name >> c.width >> c.height >> c.fx >> c.fy >> c.cx >> c.cy >>
          mount_x >> mount_y >> mount_z >> mount_yaw)) {
      *error = path + ":" + std::to_string(number) + ": expected 12 fields";
      return false;
    }
    // The simulator puts pixel edges at integers; the detector puts pixel centres there.
    c.cx -= 0.5;
    c.cy -= 0.5;
    c.camera_in_robot = Rigid2d(mount_x, mount_y, mount_yaw);
    c.mount_height = mount_z;
    frame.image_path = (base / name).string();
    if (!c.IsValid(error)) {
      *error = path + ":" + std::to_string(number) + ": " + *error;
      return false;
    }
    frames->push_back(frame);
  }
  return true;
}

bool ReadVisibility(const std::string& path, std::vector<SimVisibility>* records,
                    std::string* error) {
  std::ifstream file(path);
  if (!file) {
    *error = path + ": cannot open visibility list";
    return false;
  }
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    SimVisibility r;
    double theta;
    std::string fov, occluded, visible;
    if (!(in >> r.timestamp >> r.observer >> r.observed >> r.range >> r.bearing >>
          r.relative.x() >> r.relative.y() >> theta >> fov >> occluded >> visible >> r.image_u >>
          r.image_width)) {
      *error = path + ":" + std::to_string(number) + ": expected 13 fields";
      return false;
    }
    r.in_camera_fov = fov == "yes";
    r.occluded = occluded == "yes";
    r.visible = visible == "yes";
    records->push_back(r);
  }
  std::stable_sort(records->begin(), records->end(),
                   [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
  return true;
}

}  // namespace

bool ReadSimDataset(const std::string& dir, SimDataset* dataset, std::string* error) {
  const std::string manifest_path = (fs::path(dir) / "manifest.yaml").string();
  SimDataset result;
  result.dir = dir;
  try {
    const YAML::Node manifest = YAML::LoadFile(manifest_path);
    const YAML::Node body = manifest["robot_body"];
    if (!body || !manifest["robots"] || !manifest["robots"].IsSequence()) {
      *error = manifest_path + ": expected 'robot_body' and a 'robots' list";
      return false;
    }
    result.geometry.body_radius = body["radius"].as<double>();
    result.geometry.marker_radius = body["marker_radius"].as<double>();
    result.geometry.marker_bottom = body["marker_z_min"].as<double>();
    result.geometry.marker_top = body["marker_z_max"].as<double>();
    if (manifest["laser"] && manifest["laser"]["range_noise"]) {
      result.laser_range_noise = manifest["laser"]["range_noise"].as<double>();
    }
    for (const YAML::Node& node : manifest["robots"]) {
      SimRobot robot;
      robot.name = node["name"].as<std::string>();
      robot.log_path = (fs::path(dir) / node["log"].as<std::string>()).string();
      robot.ground_truth_path = (fs::path(dir) / node["ground_truth"].as<std::string>()).string();
      if (node["camera_index"]) {
        const std::string index = (fs::path(dir) / node["camera_index"].as<std::string>()).string();
        if (!ReadCameraIndex(index, &robot.frames, error)) return false;
      }
      result.robots.push_back(std::move(robot));
    }
    const std::string visibility = manifest["visibility"].as<std::string>("visibility.txt");
    if (!ReadVisibility((fs::path(dir) / visibility).string(), &result.visibility, error)) {
      return false;
    }
  } catch (const std::exception& e) {
    *error = manifest_path + ": " + e.what();
    return false;
  }
  if (!result.geometry.IsValid(error)) {
    *error = manifest_path + ": " + *error;
    return false;
  }
  *dataset = std::move(result);
  return true;
}

bool ReadLaserScans(const std::string& log_path, std::vector<LaserScan>* scans,
                    std::string* error) {
  auto reader = CarmenReader::Open(log_path, CarmenReaderOptions(), error);
  if (!reader) return false;
  CarmenRecord record;
  while (reader->Next(&record)) {
    if (const auto* laser = std::get_if<LaserRecord>(&record)) scans->push_back(laser->scan);
  }
  if (!reader->error().empty()) {
    *error = reader->error();
    return false;
  }
  std::stable_sort(scans->begin(), scans->end(),
                   [](const auto& a, const auto& b) { return a.timestamp < b.timestamp; });
  return true;
}

const LaserScan* NearestScan(const std::vector<LaserScan>& scans, double timestamp,
                             double max_difference) {
  const auto it = std::lower_bound(scans.begin(), scans.end(), timestamp,
                                   [](const LaserScan& s, double t) { return s.timestamp < t; });
  const LaserScan* best = nullptr;
  if (it != scans.end()) best = &*it;
  if (it != scans.begin()) {
    const LaserScan* before = &*(it - 1);
    if (!best || timestamp - before->timestamp < best->timestamp - timestamp) best = before;
  }
  if (!best || std::abs(best->timestamp - timestamp) > max_difference) return nullptr;
  return best;
}

bool PoseAt(const Trajectory& trajectory, double timestamp, Rigid2d* pose) {
  const auto it = std::lower_bound(trajectory.begin(), trajectory.end(), timestamp,
                                   [](const StampedPose& p, double t) { return p.timestamp < t; });
  if (it == trajectory.end()) return false;
  if (it->timestamp == timestamp || it == trajectory.begin()) {
    if (std::abs(it->timestamp - timestamp) > 1e-6) return false;
    *pose = it->pose;
    return true;
  }
  const StampedPose& a = *(it - 1);
  const StampedPose& b = *it;
  *pose = Interpolate(a.pose, b.pose, (timestamp - a.timestamp) / (b.timestamp - a.timestamp));
  return true;
}

}  // namespace fleetmap
