#ifndef FLEETMAP_ROBOT_AGENT_SIM_OUTPUT_WRITER_H_
#define FLEETMAP_ROBOT_AGENT_SIM_OUTPUT_WRITER_H_

#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "robot_agent/sim/simulation.h"
#include "shared/core/trajectory.h"
#include "shared/io/carmen_writer.h"

namespace fleetmap::sim {

// Writes a simulation run to a folder (formats in robot_agent/sim/README.md):
//   manifest.yaml                 robots, marker colours, sensors, file names
//   world/<name>.{pgm,yaml,world.yaml}   the ground-truth world
//   <robot>.clf                   CARMEN log: PARAM, ODOM, FLASER (odometry frame)
//   <robot>.gt.txt                ground truth "timestamp x y theta" (world frame)
//   <robot>_camera/index.txt      one line per frame; frames as <robot>_camera/frame_NNNNNN.png
//   visibility.txt                which robot could see which, per camera tick
class OutputWriter {
 public:
  // With `all_frames`, every rendered frame is written; otherwise the scenario's
  // camera.save_every / save_in_view_range policy decides.
  static std::unique_ptr<OutputWriter> Open(const std::string& dir, const Simulation& sim,
                                            std::string* error, bool all_frames = false);
  bool Write(const StepResult& step, std::string* error);
  // Writes the trajectories and flushes everything.
  bool Close(std::string* error);

 private:
  struct RobotFiles {
    std::unique_ptr<CarmenWriter> log;
    Trajectory ground_truth;
    std::string camera_dir;
    std::ofstream camera_index;
    long frames = 0;  // rendered frames seen (saved or not)
  };
  explicit OutputWriter(std::string dir) : dir_(std::move(dir)) {}

  std::string dir_;
  int save_every_ = 1;
  double save_in_view_range_ = 0.0;
  std::vector<std::string> names_;
  std::vector<RobotFiles> robots_;
  std::ofstream visibility_;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_OUTPUT_WRITER_H_
