#include "proto/conversions.h"

namespace fleetmap {

Rigid2d FromProto(const v1::Pose2d& pose) { return Rigid2d(pose.x(), pose.y(), pose.theta()); }

v1::Pose2d ToProto(const Rigid2d& pose) {
  v1::Pose2d out;
  out.set_x(pose.x());
  out.set_y(pose.y());
  out.set_theta(pose.rotation());
  return out;
}

void ToProto(const StampedPose& pose, v1::StampedPose* out) {
  out->set_timestamp(pose.timestamp);
  *out->mutable_pose() = ToProto(pose.pose);
}

EncodedGrid FromProto(const v1::Grid& grid) {
  EncodedGrid out;
  out.geometry.width = grid.width();
  out.geometry.height = grid.height();
  out.geometry.resolution = grid.resolution();
  out.geometry.origin = Eigen::Vector2d(grid.origin_x(), grid.origin_y());
  out.encoding = grid.encoding() == v1::CELL_ENCODING_PROBABILITY_UINT8
                     ? CellEncoding::kProbabilityUint8
                 : grid.encoding() == v1::CELL_ENCODING_LOG_ODDS_INT8
                     ? CellEncoding::kLogOddsInt8
                     : static_cast<CellEncoding>(0);
  out.log_odds_scale = grid.log_odds_scale();
  out.compressed = grid.cells_zstd();
  return out;
}

void ToProto(const EncodedGrid& grid, v1::Grid* out) {
  out->set_width(grid.geometry.width);
  out->set_height(grid.geometry.height);
  out->set_resolution(grid.geometry.resolution);
  out->set_origin_x(grid.geometry.origin.x());
  out->set_origin_y(grid.geometry.origin.y());
  out->set_encoding(grid.encoding == CellEncoding::kProbabilityUint8
                        ? v1::CELL_ENCODING_PROBABILITY_UINT8
                        : v1::CELL_ENCODING_LOG_ODDS_INT8);
  out->set_log_odds_scale(grid.log_odds_scale);
  out->set_cells_zstd(grid.compressed);
}

}  // namespace fleetmap
