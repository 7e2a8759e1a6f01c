#include "robot_agent/agent/proto_conversions.h"

namespace fleetmap::agent {
v1::Pose2d ToProto(const Rigid2d& pose) {
  v1::Pose2d out;
  out.set_x(pose.x());
  out.set_y(pose.y());
  out.set_theta(pose.rotation());
  return out;
}

Rigid2d FromProto(const v1::Pose2d& pose) { return Rigid2d(pose.x(), pose.y(), pose.theta()); }

namespace {

void SetStampedPose(const StampedPose& pose, v1::StampedPose* out) {
  out->set_timestamp(pose.timestamp);
  *out->mutable_pose() = ToProto(pose.pose);
}

}  // namespace

v1::SubmapUpload ToProto(const Submap& submap, int zstd_level) {
  v1::SubmapUpload out;
  out.set_submap_id(submap.submap_id);
  out.set_revision(submap.revision);
  *out.mutable_submap_in_local() = ToProto(submap.submap_in_local);
  for (const StampedPose& pose : submap.scan_poses) SetStampedPose(pose, out.add_scan_poses());
  out.set_finished(submap.finished);
  const EncodedGrid encoded = EncodeGrid(submap.grid, zstd_level);
  v1::Grid* grid = out.mutable_grid();
  grid->set_width(encoded.geometry.width);
  grid->set_height(encoded.geometry.height);
  grid->set_resolution(encoded.geometry.resolution);
  grid->set_origin_x(encoded.geometry.origin.x());
  grid->set_origin_y(encoded.geometry.origin.y());
  grid->set_encoding(encoded.encoding == CellEncoding::kLogOddsInt8
                         ? v1::CELL_ENCODING_LOG_ODDS_INT8
                         : v1::CELL_ENCODING_PROBABILITY_UINT8);
  grid->set_log_odds_scale(encoded.log_odds_scale);
  grid->set_cells_zstd(encoded.compressed);
  return out;
}

v1::UploadTrajectoryRequest ToTrajectoryRequest(const std::string& robot_id, int64_t revision,
                                                const Trajectory& trajectory) {
  v1::UploadTrajectoryRequest out;
  out.set_robot_id(robot_id);
  out.set_revision(revision);
  out.mutable_poses()->Reserve(static_cast<int>(trajectory.size()));
  for (const StampedPose& pose : trajectory) SetStampedPose(pose, out.add_poses());
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

EncodedGrid FromProto(const v1::Grid& grid) {
  EncodedGrid out;
  out.geometry.width = grid.width();
  out.geometry.height = grid.height();
  out.geometry.resolution = grid.resolution();
  out.geometry.origin = Eigen::Vector2d(grid.origin_x(), grid.origin_y());
  out.encoding = grid.encoding() == v1::CELL_ENCODING_PROBABILITY_UINT8
                     ? CellEncoding::kProbabilityUint8
                     : CellEncoding::kLogOddsInt8;
  out.log_odds_scale = grid.log_odds_scale();
  out.compressed = grid.cells_zstd();
  return out;
}

}  // namespace fleetmap::agent
