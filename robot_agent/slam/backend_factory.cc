#include "robot_agent/slam/backend_factory.h"

#include "robot_agent/slam/particle_slam.h"
#include "robot_agent/slam/scan_matching_slam.h"

namespace fleetmap {

std::vector<std::string> ParticleMotionInputs() { return {"odometry", "scan-matched"}; }

std::vector<std::string> LocalSlamAlgorithms() { return {"scan-matching", "fastslam", "rbpf"}; }

std::unique_ptr<LocalSlam> MakeLocalSlam(const BackendChoice& choice, std::string* error) {
  if (choice.algorithm == "scan-matching") {
    ScanMatchingSlamOptions options;
    options.robot_id = choice.robot_id;
    if (choice.submap_scans >= 0) options.submaps.max_scans = choice.submap_scans;
    if (choice.submap_travel >= 0.0) options.submaps.max_travel = choice.submap_travel;
    if (choice.submap_resolution > 0.0) options.submaps.grid.resolution = choice.submap_resolution;
    return std::make_unique<ScanMatchingSlam>(options);
  }
  if (choice.algorithm == "fastslam" || choice.algorithm == "rbpf") {
    ParticleSlamOptions options =
        choice.algorithm == "rbpf" ? ParticleSlamOptions::Rbpf() : ParticleSlamOptions::FastSlam();
    options.robot_id = choice.robot_id;
    options.filter.particles = choice.particles;
    options.filter.seed = choice.seed;
    if (choice.motion == "odometry" || choice.motion == "scan-matched") {
      options.scan_matched_motion = choice.motion == "scan-matched";
    } else if (!choice.motion.empty()) {
      if (error) *error = "unknown motion input '" + choice.motion + "' (known: odometry, scan-matched)";
      return nullptr;
    }
    options.loop_closure.enabled = choice.particle_loop_closure;
    return std::make_unique<ParticleSlam>(options);
  }
  std::string known;
  for (const std::string& name : LocalSlamAlgorithms()) known += (known.empty() ? "" : ", ") + name;
  if (error) *error = "unknown SLAM algorithm '" + choice.algorithm + "' (known: " + known + ")";
  return nullptr;
}

}  // namespace fleetmap
