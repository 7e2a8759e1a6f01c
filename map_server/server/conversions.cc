#include "map_server/server/conversions.h"

#include <cmath>

namespace fleetmap {
namespace {

using grpc::Status;
using grpc::StatusCode;

bool Finite(const v1::Pose2d& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.theta());
}

Status Invalid(const std::string& message) {
  return Status(StatusCode::INVALID_ARGUMENT, message);
}

Status PosesFromProto(const google::protobuf::RepeatedPtrField<v1::StampedPose>& poses,
                      const std::string& what, Trajectory* out) {
  out->clear();
  out->reserve(static_cast<size_t>(poses.size()));
  for (int i = 0; i < poses.size(); ++i) {
    const v1::StampedPose& p = poses[i];
    if (!std::isfinite(p.timestamp()) || !Finite(p.pose())) {
      return Invalid(what + "[" + std::to_string(i) + "] is not finite");
    }
    if (i > 0 && p.timestamp() < poses[i - 1].timestamp()) {
      return Invalid(what + "[" + std::to_string(i) + "] goes back in time");
    }
    out->push_back(StampedPose{p.timestamp(), FromProto(p.pose())});
  }
  return Status::OK;
}

}  // namespace

Status ValidateRobotId(const std::string& robot_id, const char* field) {
  if (robot_id.empty() || robot_id.size() > 64) {
    return Invalid(std::string(field) + " must have 1 to 64 characters");
  }
  for (char c : robot_id) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') {
      return Invalid(std::string(field) + " \"" + robot_id +
                     "\" may only contain letters, digits, '_', '-' and '.'");
    }
  }
  return Status::OK;
}

Status FromProto(const v1::RegisterRobotRequest& request, double now, RobotRecord* robot) {
  Status status = ValidateRobotId(request.robot_id(), "robot_id");
  if (!status.ok()) return status;
  if (request.name().size() > 256 || request.sensor_description().size() > 4096 ||
      request.algorithm().size() > 256) {
    return Status(StatusCode::RESOURCE_EXHAUSTED, "name, sensor_description or algorithm too long");
  }
  robot->robot_id = request.robot_id();
  robot->name = request.name();
  robot->sensor_description = request.sensor_description();
  robot->algorithm = request.algorithm();
  robot->registered_unix_time = now;
  robot->local_in_global.reset();
  if (request.has_local_in_global()) {
    if (!Finite(request.local_in_global())) return Invalid("local_in_global is not finite");
    robot->local_in_global = FromProto(request.local_in_global());
  }
  robot->localization_only = request.localization_only();
  return Status::OK;
}

Status FromProto(const std::string& robot_id, const v1::SubmapUpload& upload,
                 const UploadLimits& limits, Submap* submap) {
  if (upload.submap_id() < 0 || upload.revision() < 0) {
    return Invalid("submap_id and revision must not be negative");
  }
  if (!Finite(upload.submap_in_local())) return Invalid("submap_in_local is not finite");
  if (upload.scan_poses_size() > limits.max_scan_poses) {
    return Status(StatusCode::RESOURCE_EXHAUSTED,
                  std::to_string(upload.scan_poses_size()) + " scan poses exceed the limit of " +
                      std::to_string(limits.max_scan_poses));
  }
  if (upload.grid().encoding() == v1::CELL_ENCODING_UNSPECIFIED) {
    return Invalid("grid.encoding must be set");
  }
  submap->robot_id = robot_id;
  submap->submap_id = upload.submap_id();
  submap->revision = upload.revision();
  submap->submap_in_local = FromProto(upload.submap_in_local());
  submap->finished = upload.finished();
  Status status = PosesFromProto(upload.scan_poses(), "scan_poses", &submap->scan_poses);
  if (!status.ok()) return status;
  GridDecodeError code;
  std::string error;
  if (!DecodeGrid(FromProto(upload.grid()), limits.submap_grid, OccupancyGridOptions(),
                  &submap->grid, &code, &error)) {
    return Status(code == GridDecodeError::kTooLarge ? StatusCode::RESOURCE_EXHAUSTED
                                                     : StatusCode::INVALID_ARGUMENT,
                  "grid: " + error);
  }
  return Status::OK;
}

Status FromProto(const v1::UploadTrajectoryRequest& request, const UploadLimits& limits,
                 double now, TrajectoryRecord* trajectory) {
  Status status = ValidateRobotId(request.robot_id(), "robot_id");
  if (!status.ok()) return status;
  if (request.revision() < 0) return Invalid("revision must not be negative");
  if (request.poses_size() > limits.max_trajectory_poses) {
    return Status(StatusCode::RESOURCE_EXHAUSTED,
                  std::to_string(request.poses_size()) + " poses exceed the limit of " +
                      std::to_string(limits.max_trajectory_poses));
  }
  trajectory->robot_id = request.robot_id();
  trajectory->revision = request.revision();
  trajectory->received_unix_time = now;
  return PosesFromProto(request.poses(), "poses", &trajectory->poses);
}

Status FromProto(const std::string& observer_id, const v1::Detection& d, double now,
                 DetectionRecord* record) {
  Status status = ValidateRobotId(d.observed_id(), "observed_id");
  if (!status.ok()) return status;
  if (d.detection_id() < 0) return Invalid("detection_id must not be negative");
  const double values[] = {d.timestamp(), d.x(), d.y(), d.cov_xx(), d.cov_xy(), d.cov_yy(),
                           d.relative_heading(), d.relative_heading_variance(), d.confidence()};
  for (double v : values) {
    if (!std::isfinite(v)) return Invalid("detection has a non-finite number");
  }
  if (!(d.cov_xx() > 0.0 && d.cov_yy() > 0.0 && d.cov_xx() * d.cov_yy() > d.cov_xy() * d.cov_xy())) {
    return Invalid("covariance must be symmetric positive definite");
  }
  if (d.confidence() < 0.0 || d.confidence() > 1.0) return Invalid("confidence must be in [0, 1]");
  if (d.relative_heading_variance() < 0.0) {
    return Invalid("relative_heading_variance must not be negative");
  }
  record->detection_id = d.detection_id();
  record->received_unix_time = now;
  RobotDetection& out = record->detection;
  out.observer_id = observer_id;
  out.observed_id = d.observed_id();
  out.timestamp = d.timestamp();
  out.position_in_observer = Eigen::Vector2d(d.x(), d.y());
  out.covariance << d.cov_xx(), d.cov_xy(), d.cov_xy(), d.cov_yy();
  out.relative_heading.reset();
  if (d.has_relative_heading()) out.relative_heading = d.relative_heading();
  out.relative_heading_variance = d.relative_heading_variance();
  out.confidence = d.confidence();
  return Status::OK;
}

void ToProto(const RobotPlacementRecord& placement, v1::RobotPlacement* out) {
  out->set_robot_id(placement.robot_id);
  out->set_placed(placement.placed);
  if (placement.placed) *out->mutable_local_in_global() = ToProto(placement.local_in_global);
  if (placement.placed && placement.start_in_global) {
    *out->mutable_start_in_global() = ToProto(*placement.start_in_global);
  }
  out->set_source(placement.source);
  out->set_note(placement.note);
}

void ToProto(const VersionRecord& version, v1::VersionInfo* out) {
  out->set_version(version.version);
  out->set_created_unix_time(version.created_unix_time);
  v1::Provenance* provenance = out->mutable_provenance();
  provenance->set_trigger(version.trigger);
  for (const std::string& id : version.trigger_robot_ids) provenance->add_trigger_robot_ids(id);
  for (const SubmapKey& key : version.new_submaps) {
    auto* ref = provenance->add_new_submaps();
    ref->set_robot_id(key.robot_id);
    ref->set_submap_id(key.submap_id);
    ref->set_revision(key.revision);
  }
  for (const DetectionRef& d : version.new_detections) {
    auto* ref = provenance->add_new_detections();
    ref->set_observer_id(d.observer_id);
    ref->set_detection_id(d.detection_id);
  }
  for (const auto& [name, value] : version.quality) (*provenance->mutable_quality())[name] = value;
  provenance->set_merge_engine(version.merge_engine);
  for (const RobotPlacementRecord& p : version.placements) ToProto(p, out->add_placements());
  out->set_width(version.geometry.width);
  out->set_height(version.geometry.height);
  out->set_resolution(version.geometry.resolution);
  out->set_origin_x(version.geometry.origin.x());
  out->set_origin_y(version.geometry.origin.y());
  out->set_grid_available(version.grid_available);
}

void ToAck(PutOutcome outcome, const std::string& error, v1::ItemAck* ack) {
  const Status status = ToStatus(outcome, "item", error);
  ack->set_code(static_cast<int32_t>(status.error_code()));
  ack->set_message(status.error_message());
  ack->set_duplicate(outcome == PutOutcome::kDuplicate);
}

Status ToStatus(PutOutcome outcome, const std::string& what, const std::string& error) {
  switch (outcome) {
    case PutOutcome::kInserted:
    case PutOutcome::kDuplicate:
      return Status::OK;
    case PutOutcome::kOutOfOrder:
      return Status(StatusCode::FAILED_PRECONDITION,
                    what + " is older than the newest revision stored; send newer revisions only");
    case PutOutcome::kUnknownRobot:
      return Status(StatusCode::NOT_FOUND, "unknown robot: call RegisterRobot first");
    case PutOutcome::kError:
      break;
  }
  return Status(StatusCode::INTERNAL, "storage failed: " + error + " (retry later)");
}

}  // namespace fleetmap
