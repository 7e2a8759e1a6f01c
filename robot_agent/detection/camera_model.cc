#include "robot_agent/detection/camera_model.h"

namespace fleetmap {

bool CameraModel::IsValid(std::string* error) const {
  if (width < 8 || height < 8 || width > 16384 || height > 16384) {
    *error = "camera image size " + std::to_string(width) + "x" + std::to_string(height) +
             " is out of range";
    return false;
  }
  if (!(fx > 0.0) || !(fy > 0.0) || !std::isfinite(fx) || !std::isfinite(fy)) {
    *error = "camera focal lengths must be positive";
    return false;
  }
  if (!std::isfinite(cx) || !std::isfinite(cy) || !camera_in_robot.IsFinite() ||
      !std::isfinite(mount_height)) {
    *error = "camera principal point and mount must be finite";
    return false;
  }
  return true;
}

bool MarkerGeometry::IsValid(std::string* error) const {
  if (!(marker_radius > 0.0) || !(body_radius > 0.0) || !(marker_top > marker_bottom) ||
      !std::isfinite(marker_top) || !std::isfinite(marker_bottom) ||
      !std::isfinite(marker_radius) || !std::isfinite(body_radius)) {
    *error = "marker geometry needs positive radii and marker_top > marker_bottom";
    return false;
  }
  return true;
}

}  // namespace fleetmap
