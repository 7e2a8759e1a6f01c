#ifndef FLEETMAP_ROBOT_AGENT_SLAM_BACKEND_FACTORY_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_BACKEND_FACTORY_H_

#include <memory>
#include <string>
#include <vector>

#include "robot_agent/slam/local_slam.h"

namespace fleetmap {

// Settings the command-line tools can choose per run; each backend keeps its own defaults for
// everything else.
struct BackendChoice {
  std::string algorithm = "scan-matching";
  std::string robot_id = "robot";
  int particles = 30;  // particle filters only
  unsigned seed = 1;   // particle filters only
  // Particle filters only: the filter's motion input, "odometry" (raw) or "scan-matched" (the
  // per-scan scan-matched motion: the paper's remedy for FastSLAM's particle depletion); empty
  // keeps the backend's default (ParticleSlamOptions::scan_matched_motion).
  std::string motion;
  // Particle filters only: global loop closure over the best particle's trajectory
  // (ParticleSlamOptions::loop_closure; on by default, see ParticleLoopClosureOptions).
  bool particle_loop_closure = true;
  // Scan-matching only: submap limits (SubmapOptions::max_scans, max_travel); negative keeps the
  // backend's default.
  int submap_scans = -1;
  double submap_travel = -1.0;
  // Scan-matching only: the submaps' cell size (metres); non-positive keeps the backend's.
  double submap_resolution = -1.0;
};

// The motion inputs BackendChoice::motion accepts.
std::vector<std::string> ParticleMotionInputs();

// The algorithm names MakeLocalSlam accepts.
std::vector<std::string> LocalSlamAlgorithms();

// A backend by name; nullptr and a message listing the known names when the algorithm or the
// motion input is unknown.
std::unique_ptr<LocalSlam> MakeLocalSlam(const BackendChoice& choice, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_BACKEND_FACTORY_H_
