#ifndef FLEETMAP_ROBOT_AGENT_SIM_VISIBILITY_H_
#define FLEETMAP_ROBOT_AGENT_SIM_VISIBILITY_H_

#include <string>
#include <vector>

#include "robot_agent/sim/camera_model.h"
#include "robot_agent/sim/world.h"
#include "shared/core/rigid2d.h"

namespace fleetmap::sim {

// Ground truth of whether one robot could see another at a time.
struct VisibilityRecord {
  double timestamp = 0.0;
  int observer = 0;  // robot indices
  int observed = 0;
  double range = 0.0;    // metres between the robot centres
  double bearing = 0.0;  // of the observed centre, in the observer's robot frame (radians)
  Rigid2d relative;      // observed robot pose in the observer's robot frame
  bool in_camera_fov = false;  // the marker's centre projects inside the image, in front
  bool occluded = false;       // a wall or another robot blocks the camera -> marker line
  bool visible = false;        // in_camera_fov && !occluded && within the camera's max depth
  double image_u = -1.0;       // marker centre column (when in front of the camera)
  double image_width = 0.0;    // apparent marker width, pixels
};

// One record per ordered pair of robots, from the true poses. `body_radius` is the radius other
// robots block the view with; `marker_radius` and `marker_z` describe the seen marker.
std::vector<VisibilityRecord> ComputeVisibility(double timestamp, const World& world,
                                                const std::vector<Rigid2d>& robots_in_world,
                                                const CameraModel& camera, double body_radius,
                                                double marker_radius);

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_VISIBILITY_H_
