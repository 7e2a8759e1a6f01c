#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_CAMERA_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_CAMERA_MODEL_H_

#include <cmath>
#include <string>

#include "shared/core/rigid2d.h"

namespace fleetmap {

// A level pinhole camera on the robot. The optical axis is the camera frame's +x, image columns
// grow to the right (towards camera -y) and rows grow downwards. Pixel centres sit at integer
// coordinates, so the image spans [-0.5, width - 0.5].
struct CameraModel {
  int width = 640;
  int height = 480;
  double fx = 554.2563;  // 60 degree horizontal field at 640 columns
  double fy = 554.2563;
  double cx = 319.5;
  double cy = 239.5;
  Rigid2d camera_in_robot;     // mount on the robot (planar part)
  double mount_height = 0.55;  // optical centre above the floor, metres

  // Bearing of the ray through column `u`, radians, + to the left, in the camera frame.
  double BearingOfColumn(double u) const { return std::atan2(cx - u, fx); }
  double ColumnOfBearing(double bearing) const { return cx - fx * std::tan(bearing); }
  // Row where a point `z` metres above the floor appears at forward depth `depth`.
  double RowOfHeight(double z, double depth) const { return cy - fy * (z - mount_height) / depth; }
  // Half of the horizontal field of view, radians.
  double HalfFieldOfView() const { return std::atan2(cx + 0.5, fx); }

  // False with a reason when the numbers cannot describe a camera.
  bool IsValid(std::string* error) const;
};

// The coloured cylinder each robot carries, and the robot body the laser sees.
struct MarkerGeometry {
  double marker_radius = 0.20;  // metres (the simulator's RobotBody defaults)
  double marker_bottom = 0.35;  // metres above the floor
  double marker_top = 0.65;
  double body_radius = 0.20;    // the robot's body, a cylinder centred on the robot, seen by laser

  double marker_height() const { return marker_top - marker_bottom; }
  bool IsValid(std::string* error) const;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_CAMERA_MODEL_H_
