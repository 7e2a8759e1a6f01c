#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_TOOLS_SIM_DATASET_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_TOOLS_SIM_DATASET_H_

// Reads a fleetmap-sim output folder (robot_agent/sim/output_writer.h) for the detection tools:
// manifest.yaml, <robot>_camera/index.txt, <robot>.clf, <robot>.gt.txt and visibility.txt. Only
// the file formats are shared with the simulator, not its code.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/detection/camera_model.h"
#include "shared/core/laser_scan.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

struct SimCameraFrame {
  double timestamp = 0.0;
  std::string image_path;
  CameraModel camera;  // intrinsics converted to pixel centres at integers
};

struct SimVisibility {
  double timestamp = 0.0;
  std::string observer, observed;
  double range = 0.0, bearing = 0.0;             // robot centres, observer's robot frame
  Eigen::Vector2d relative = Eigen::Vector2d::Zero();
  bool in_camera_fov = false, occluded = false, visible = false;
  double image_u = -1.0, image_width = 0.0;
};

struct SimRobot {
  std::string name;
  std::string log_path;
  std::string ground_truth_path;
  std::vector<SimCameraFrame> frames;  // empty when the robot has no camera
};

struct SimDataset {
  std::string dir;
  MarkerGeometry geometry;
  double laser_range_noise = 0.01;
  std::vector<SimRobot> robots;
  std::vector<SimVisibility> visibility;  // sorted by time
};

// False with a message naming the file and line on any missing or malformed part.
bool ReadSimDataset(const std::string& dir, SimDataset* dataset, std::string* error);

// The FLASER scans of a CARMEN log, in time order.
bool ReadLaserScans(const std::string& log_path, std::vector<LaserScan>* scans,
                    std::string* error);
// The scan closest in time to `timestamp`, or nullptr when none lies within `max_difference`.
const LaserScan* NearestScan(const std::vector<LaserScan>& scans, double timestamp,
                             double max_difference);
// Pose at `timestamp` interpolated from a time-ordered trajectory; false outside its span.
bool PoseAt(const Trajectory& trajectory, double timestamp, Rigid2d* pose);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_TOOLS_SIM_DATASET_H_
