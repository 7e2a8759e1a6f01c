#include "robot_agent/sim/output_writer.h"

#include <cstdio>
#include <filesystem>

#include "robot_agent/sim/appearance.h"
#include "robot_agent/sim/world_io.h"
#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap::sim {
namespace {

namespace fs = std::filesystem;

std::string F(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

bool WriteManifest(const std::string& path, const Simulation& sim, std::string* error) {
  const Scenario& s = sim.scenario();
  const CameraIntrinsics& k = sim.camera().intrinsics();
  std::ofstream out(path);
  out << "# fleetmap-sim run (formats: robot_agent/sim/README.md)\n"
      << "scenario: " << s.name << "\nworld: " << sim.world().name
      << "\nworld_map: world/" << sim.world().name << ".yaml\n"
      << "seed: " << s.seed << "\ntime_step: " << F("%.6f", s.time_step) << "\n"
      << "robot_body: {radius: " << F("%.3f", s.body.radius)
      << ", body_height: " << F("%.3f", s.body.body_height)
      << ", marker_radius: " << F("%.3f", s.body.marker_radius)
      << ", marker_z_min: " << F("%.3f", s.body.marker_z_min)
      << ", marker_z_max: " << F("%.3f", s.body.marker_z_max) << "}\n"
      << "laser: {rate: " << F("%.3f", s.laser.rate_hz) << ", beams: " << s.laser.beams
      << ", fov_deg: " << F("%.3f", s.laser.fov_deg)
      << ", max_range: " << F("%.3f", s.laser.max_range)
      << ", range_noise: " << F("%.4f", s.laser.range_noise) << "}\n"
      << "camera: {enabled: " << (s.camera.enabled ? "true" : "false")
      << ", rate: " << F("%.3f", s.camera.rate_hz) << ", width: " << s.camera.width
      << ", height: " << s.camera.height << ", fx: " << F("%.6f", k.fx)
      << ", fy: " << F("%.6f", k.fy) << ", cx: " << F("%.3f", k.cx)
      << ", cy: " << F("%.3f", k.cy) << ", mount_x: " << F("%.4f", s.camera.mount_x)
      << ", mount_y: " << F("%.4f", s.camera.mount_y)
      << ", mount_z: " << F("%.4f", s.camera.mount_z)
      << ", mount_yaw: " << F("%.6f", s.camera.mount_yaw) << "}\n"
      << "robots:\n";
  for (size_t i = 0; i < sim.robots().size(); ++i) {
    const SimRobotInfo& robot = sim.robots()[i];
    const Rigid2d& start = robot.route.start;
    out << "  - name: " << robot.name << "\n    index: " << i << "\n    marker_rgb: ["
        << int(robot.marker.r) << ", " << int(robot.marker.g) << ", " << int(robot.marker.b)
        << "]\n    marker_hue_deg: " << F("%.1f", HueDegrees(robot.marker))
        << "\n    start: {x: " << F("%.6f", start.x()) << ", y: " << F("%.6f", start.y())
        << ", theta: " << F("%.6f", start.rotation()) << "}\n"
        << "    planned_path_length: " << F("%.3f", PathLength(robot.route.path)) << "\n"
        << "    log: " << robot.name << ".clf\n    ground_truth: " << robot.name
        << ".gt.txt\n";
    if (s.camera.enabled) out << "    camera_index: " << robot.name << "_camera/index.txt\n";
  }
  out << "visibility: visibility.txt\n";
  if (!out) {
    *error = path + ": cannot write";
    return false;
  }
  return true;
}

}  // namespace

std::unique_ptr<OutputWriter> OutputWriter::Open(const std::string& dir, const Simulation& sim,
                                                 std::string* error, bool all_frames) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    *error = "cannot create output folder " + dir + ": " + ec.message();
    return nullptr;
  }
  std::unique_ptr<OutputWriter> writer(new OutputWriter(dir));
  writer->save_every_ = all_frames ? 1 : sim.scenario().camera.save_every;
  writer->save_in_view_range_ = sim.scenario().camera.save_in_view_range;
  if (!WriteManifest((fs::path(dir) / "manifest.yaml").string(), sim, error)) return nullptr;
  if (!SaveWorld((fs::path(dir) / "world").string(), sim.world(), error)) return nullptr;
  const Scenario& s = sim.scenario();
  writer->robots_.resize(sim.robots().size());
  for (size_t i = 0; i < sim.robots().size(); ++i) {
    const std::string& name = sim.robots()[i].name;
    RobotFiles& files = writer->robots_[i];
    const std::string log_path = (fs::path(dir) / (name + ".clf")).string();
    files.log = std::make_unique<CarmenWriter>(log_path, name);
    if (!files.log->ok()) {
      *error = log_path + ": cannot write";
      return nullptr;
    }
    files.log->WriteParam("robot_name", name, s.start_time);
    files.log->WriteParam("simulator_scenario", s.name, s.start_time);
    files.log->WriteParam("simulator_world", sim.world().name, s.start_time);
    files.log->WriteParam("robot_front_laser_offset", F("%.4f", s.laser.mount.x()),
                          s.start_time);
    if (s.camera.enabled) {
      files.camera_dir = (fs::path(dir) / (name + "_camera")).string();
      fs::create_directories(files.camera_dir, ec);
      files.camera_index.open((fs::path(files.camera_dir) / "index.txt").string());
      files.camera_index << "# timestamp file width height fx fy cx cy mount_x mount_y mount_z "
                            "mount_yaw\n";
      if (ec || !files.camera_index) {
        *error = files.camera_dir + ": cannot write camera frames";
        return nullptr;
      }
    }
    writer->names_.push_back(name);
  }
  writer->visibility_.open((fs::path(dir) / "visibility.txt").string());
  writer->visibility_ << "# timestamp observer observed range bearing rel_x rel_y rel_theta "
                         "in_camera_fov occluded visible image_u image_width\n";
  if (!writer->visibility_) {
    *error = dir + "/visibility.txt: cannot write";
    return nullptr;
  }
  return writer;
}

bool OutputWriter::Write(const StepResult& step, std::string* error) {
  char line[512];
  std::vector<bool> robot_in_view(robots_.size(), false);
  for (const VisibilityRecord& r : step.visibility) {
    if (r.in_camera_fov && r.range <= save_in_view_range_) {
      robot_in_view[static_cast<size_t>(r.observer)] = true;
    }
  }
  for (const SensorPacket& packet : step.packets) {
    RobotFiles& files = robots_[static_cast<size_t>(packet.robot_index)];
    if (packet.odometry) files.log->WriteOdometry(*packet.odometry);
    if (packet.laser) files.log->WriteLaser(*packet.laser);
    if (packet.odometry || packet.laser) {
      files.ground_truth.push_back(StampedPose{packet.timestamp, packet.ground_truth});
    }
    if (packet.camera && files.camera_index.is_open()) {
      const CameraFrame& frame = *packet.camera;
      const long sequence = files.frames++;
      if (sequence % save_every_ != 0 && !robot_in_view[static_cast<size_t>(packet.robot_index)]) {
        continue;
      }
      std::snprintf(line, sizeof(line), "frame_%06ld.png", sequence);
      const std::string file = line;
      if (!WritePng((fs::path(files.camera_dir) / file).string(), frame.image.width,
                    frame.image.height, 3, frame.image.pixels, error)) {
        return false;
      }
      std::snprintf(line, sizeof(line), "%.6f %s %d %d %.6f %.6f %.3f %.3f %.4f %.4f %.4f %.6f\n",
                    frame.timestamp, file.c_str(), frame.image.width, frame.image.height,
                    frame.intrinsics.fx, frame.intrinsics.fy, frame.intrinsics.cx,
                    frame.intrinsics.cy, frame.mount.x(), frame.mount.y(), frame.mount_z,
                    frame.mount.rotation());
      files.camera_index << line;
    }
  }
  for (const VisibilityRecord& r : step.visibility) {
    std::snprintf(line, sizeof(line),
                  "%.6f %s %s %.4f %.5f %.4f %.4f %.5f %s %s %s %.1f %.1f\n", r.timestamp,
                  names_[static_cast<size_t>(r.observer)].c_str(),
                  names_[static_cast<size_t>(r.observed)].c_str(), r.range, r.bearing,
                  r.relative.x(), r.relative.y(), r.relative.rotation(),
                  r.in_camera_fov ? "yes" : "no", r.occluded ? "yes" : "no",
                  r.visible ? "yes" : "no", r.image_u, r.image_width);
    visibility_ << line;
  }
  if (!visibility_) {
    *error = dir_ + "/visibility.txt: write failed";
    return false;
  }
  return true;
}

bool OutputWriter::Close(std::string* error) {
  for (size_t i = 0; i < robots_.size(); ++i) {
    RobotFiles& files = robots_[i];
    if (!files.log->Close()) {
      *error = dir_ + "/" + names_[i] + ".clf: write failed";
      return false;
    }
    const std::string gt_path = (fs::path(dir_) / (names_[i] + ".gt.txt")).string();
    if (!WriteTrajectory(gt_path, files.ground_truth, error)) return false;
    if (files.camera_index.is_open()) {
      files.camera_index.close();
      if (!files.camera_index) {
        *error = files.camera_dir + "/index.txt: write failed";
        return false;
      }
    }
  }
  visibility_.close();
  if (!visibility_) {
    *error = dir_ + "/visibility.txt: write failed";
    return false;
  }
  return true;
}

}  // namespace fleetmap::sim
