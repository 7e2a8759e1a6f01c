#include "robot_agent/agent/proto_conversions.h"

namespace fleetmap::agent {

v1::SubmapUpload ToProto(const Submap& submap, int zstd_level) {
  v1::SubmapUpload out;
  out.set_submap_id(submap.submap_id);
  out.set_revision(submap.revision);
  *out.mutable_submap_in_local() = ToProto(submap.submap_in_local);
  for (const StampedPose& pose : submap.scan_poses) ToProto(pose, out.add_scan_poses());
  out.set_finished(submap.finished);
  ToProto(EncodeGrid(submap.grid, zstd_level), out.mutable_grid());
  return out;
}

v1::UploadTrajectoryRequest ToTrajectoryRequest(const std::string& robot_id, int64_t revision,
                                                const Trajectory& trajectory) {
  v1::UploadTrajectoryRequest out;
  out.set_robot_id(robot_id);
  out.set_revision(revision);
  out.mutable_poses()->Reserve(static_cast<int>(trajectory.size()));
  for (const StampedPose& pose : trajectory) ToProto(pose, out.add_poses());
  return out;
}

v1::Detection ToProto(const RobotDetection& detection, int64_t detection_id) {
  v1::Detection out;
  out.set_detection_id(detection_id);
  out.set_observed_id(detection.observed_id);
  out.set_timestamp(detection.timestamp);
  out.set_x(detection.position_in_observer.x());
  out.set_y(detection.position_in_observer.y());
  out.set_cov_xx(detection.covariance(0, 0));
  out.set_cov_xy(detection.covariance(0, 1));
  out.set_cov_yy(detection.covariance(1, 1));
  out.set_has_relative_heading(detection.relative_heading.has_value());
  if (detection.relative_heading) {
    out.set_relative_heading(*detection.relative_heading);
    out.set_relative_heading_variance(detection.relative_heading_variance);
  }
  out.set_confidence(detection.confidence);
  return out;
}

}  // namespace fleetmap::agent
