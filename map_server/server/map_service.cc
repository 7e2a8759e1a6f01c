// MapServiceImpl: the robot-side (upload) handlers.
#include "map_server/server/map_service.h"

#include <chrono>

namespace fleetmap {
namespace {

using grpc::Status;
using grpc::StatusCode;

double SystemUnixTime() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

MapServiceOptions WithDefaults(MapServiceOptions options) {
  if (!options.clock) options.clock = SystemUnixTime;
  return options;
}

// Checks that a batch names a registered robot and has an acceptable number of items; fills
// `robot` with its record when given.
Status CheckBatch(MapStore* store, const std::string& robot_id, const char* field, int items,
                  int max_items, RobotRecord* robot = nullptr) {
  Status status = ValidateRobotId(robot_id, field);
  if (!status.ok()) return status;
  if (items == 0) return Status(StatusCode::INVALID_ARGUMENT, "the request has no items");
  if (items > max_items) {
    return Status(StatusCode::RESOURCE_EXHAUSTED,
                  std::to_string(items) + " items exceed the limit of " +
                      std::to_string(max_items) + " per request; send smaller batches");
  }
  const std::optional<RobotRecord> record = store->GetRobot(robot_id);
  if (!record) {
    return Status(StatusCode::NOT_FOUND,
                  "unknown robot \"" + robot_id + "\": call RegisterRobot first");
  }
  if (robot) *robot = *record;
  return Status::OK;
}

}  // namespace

MapServiceImpl::MapServiceImpl(const MapServiceOptions& options, MapStore* store,
                               MergeWorker* worker, VersionFeed* feed)
    : options_(WithDefaults(options)), store_(store), worker_(worker), feed_(feed) {}

Status MapServiceImpl::RegisterRobot(grpc::ServerContext* /*context*/,
                                     const v1::RegisterRobotRequest* request,
                                     v1::RegisterRobotResponse* response) {
  RobotRecord robot;
  Status status = FromProto(*request, Now(), &robot);
  if (!status.ok()) return status;
  // Its submaps are part of the global map; a localizing robot's poses are in another frame.
  if (robot.localization_only && store_->CountSubmapIds(robot.robot_id) > 0) {
    return Status(StatusCode::FAILED_PRECONDITION,
                  "robot \"" + robot.robot_id +
                      "\" has mapped (its submaps are stored): give the localizing robot an id "
                      "of its own");
  }
  bool existed = false;
  std::string error;
  if (!store_->PutRobot(robot, &existed, &error)) {
    return Status(StatusCode::INTERNAL, "storage failed: " + error + " (retry later)");
  }
  response->set_already_registered(existed);
  MergeEvent event;
  event.kind = MergeEvent::Kind::kRobotRegistered;
  event.robot_id = robot.robot_id;
  worker_->Submit(std::move(event));
  return Status::OK;
}

Status MapServiceImpl::UploadSubmaps(grpc::ServerContext* /*context*/,
                                     const v1::UploadSubmapsRequest* request,
                                     v1::UploadSubmapsResponse* response) {
  RobotRecord robot;
  Status status = CheckBatch(store_, request->robot_id(), "robot_id", request->submaps_size(),
                             options_.limits.max_submaps_per_request, &robot);
  if (!status.ok()) return status;
  if (robot.localization_only) {
    return Status(StatusCode::FAILED_PRECONDITION,
                  "robot \"" + robot.robot_id +
                      "\" is registered for localization only (it localizes in a known map) and "
                      "sends no submaps; register it again without localization_only to map");
  }
  for (const v1::SubmapUpload& upload : request->submaps()) {
    v1::ItemAck* ack = response->add_acks();
    ack->set_id(upload.submap_id());
    ack->set_revision(upload.revision());
    auto stored = std::make_shared<StoredSubmap>();
    status = FromProto(request->robot_id(), upload, options_.limits, &stored->submap);
    if (!status.ok()) {
      ack->set_code(static_cast<int32_t>(status.error_code()));
      ack->set_message(status.error_message());
      continue;
    }
    stored->received_unix_time = Now();
    std::string error;
    const PutOutcome outcome =
        store_->PutSubmap(stored->submap, stored->received_unix_time, &stored->seq, &error);
    ToAck(outcome, error, ack);
    if (outcome == PutOutcome::kInserted) {
      MergeEvent event;
      event.kind = MergeEvent::Kind::kSubmapStored;
      event.robot_id = request->robot_id();
      event.submap = std::move(stored);
      worker_->Submit(std::move(event));
    }
  }
  return Status::OK;
}

Status MapServiceImpl::UploadTrajectory(grpc::ServerContext* /*context*/,
                                        const v1::UploadTrajectoryRequest* request,
                                        v1::UploadTrajectoryResponse* response) {
  TrajectoryRecord trajectory;
  Status status = FromProto(*request, options_.limits, Now(), &trajectory);
  if (!status.ok()) return status;
  std::string error;
  const PutOutcome outcome = store_->PutTrajectory(trajectory, &error);
  status = ToStatus(outcome, "trajectory revision " + std::to_string(request->revision()), error);
  if (!status.ok()) return status;
  response->set_duplicate(outcome == PutOutcome::kDuplicate);
  if (outcome == PutOutcome::kInserted) {
    MergeEvent event;
    event.kind = MergeEvent::Kind::kTrajectoryStored;
    event.robot_id = request->robot_id();
    worker_->Submit(std::move(event));
  }
  return Status::OK;
}

Status MapServiceImpl::ReportDetections(grpc::ServerContext* /*context*/,
                                        const v1::ReportDetectionsRequest* request,
                                        v1::ReportDetectionsResponse* response) {
  Status status = CheckBatch(store_, request->observer_id(), "observer_id",
                             request->detections_size(),
                             options_.limits.max_detections_per_request);
  if (!status.ok()) return status;
  for (const v1::Detection& detection : request->detections()) {
    v1::ItemAck* ack = response->add_acks();
    ack->set_id(detection.detection_id());
    DetectionRecord record;
    status = FromProto(request->observer_id(), detection, Now(), &record);
    if (!status.ok()) {
      ack->set_code(static_cast<int32_t>(status.error_code()));
      ack->set_message(status.error_message());
      continue;
    }
    std::string error;
    const PutOutcome outcome = store_->PutDetection(record, &record.seq, &error);
    ToAck(outcome, error, ack);
    if (outcome == PutOutcome::kInserted) {
      MergeEvent event;
      event.kind = MergeEvent::Kind::kDetectionStored;
      event.robot_id = request->observer_id();
      event.detection = std::move(record);
      worker_->Submit(std::move(event));
    }
  }
  return Status::OK;
}

}  // namespace fleetmap
