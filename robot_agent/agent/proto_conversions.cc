#include "robot_agent/agent/proto_conversions.h"

#include <cmath>

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

v1::PoseDensity ToProto(const PoseDensity& density) {
  v1::PoseDensity out;
  out.set_observer_id(density.observer_id);
  out.set_observed_id(density.observed_id);
  out.set_timestamp(density.timestamp);
  out.set_has_heading(density.has_heading);
  for (const PoseDensityKernel& kernel : density.kernels) {
    v1::PoseDensityKernel* k = out.add_kernels();
    k->set_weight(kernel.weight);
    k->set_x(kernel.mean.x());
    k->set_y(kernel.mean.y());
    k->set_var_x(kernel.covariance(0, 0));
    k->set_cov_xy(kernel.covariance(0, 1));
    k->set_var_y(kernel.covariance(1, 1));
    k->set_theta(kernel.heading);
    k->set_var_theta(kernel.heading_variance);
  }
  return out;
}

bool FromProto(const v1::PoseDensity& message, PoseDensity* density) {
  *density = PoseDensity();
  density->observer_id = message.observer_id();
  density->observed_id = message.observed_id();
  density->timestamp = message.timestamp();
  density->has_heading = message.has_heading();
  double total = 0.0;
  for (const v1::PoseDensityKernel& k : message.kernels()) {
    PoseDensityKernel kernel;
    kernel.weight = k.weight();
    kernel.mean = Eigen::Vector2d(k.x(), k.y());
    kernel.covariance << k.var_x(), k.cov_xy(), k.cov_xy(), k.var_y();
    kernel.heading = k.theta();
    kernel.heading_variance = k.var_theta();
    const bool usable =
        std::isfinite(kernel.weight) && kernel.weight > 0.0 && kernel.mean.allFinite() &&
        kernel.covariance.allFinite() && k.var_x() > 0.0 && k.var_y() > 0.0 &&
        k.var_x() * k.var_y() > k.cov_xy() * k.cov_xy() && std::isfinite(kernel.heading) &&
        std::isfinite(kernel.heading_variance) && kernel.heading_variance >= 0.0;
    if (!usable) return false;
    total += kernel.weight;
    density->kernels.push_back(kernel);
  }
  if (density->kernels.empty() || !std::isfinite(density->timestamp)) return false;
  for (PoseDensityKernel& kernel : density->kernels) kernel.weight /= total;
  return true;
}

}  // namespace fleetmap::agent
