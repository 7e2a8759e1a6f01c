// MapServiceImpl: the query-side handlers.
#include <chrono>

#include "map_server/server/grid_region.h"
#include "map_server/server/map_service.h"

namespace fleetmap {
namespace {

using grpc::Status;
using grpc::StatusCode;

Status NotFound(const std::string& message) { return Status(StatusCode::NOT_FOUND, message); }

}  // namespace

Status MapServiceImpl::SelectVersion(const v1::GetGlobalMapRequest& request,
                                     std::shared_ptr<const GlobalMapSnapshot>* snapshot) {
  const std::shared_ptr<const GlobalMapSnapshot> latest = feed_->Latest();
  const int64_t latest_version = latest ? latest->info.version : 0;
  if (request.version() < 0 || !std::isfinite(request.as_of_unix_time())) {
    return Status(StatusCode::INVALID_ARGUMENT, "version must be >= 0 and as_of_unix_time finite");
  }
  std::optional<VersionRecord> record;
  if (request.version() > 0) {
    if (request.version() == latest_version) {
      *snapshot = latest;
      return Status::OK;
    }
    record = store_->GetVersion(request.version());
    if (!record) {
      return NotFound("version " + std::to_string(request.version()) +
                      " does not exist (latest is " + std::to_string(latest_version) + ")");
    }
  } else if (request.as_of_unix_time() > 0.0) {
    record = store_->VersionAtTime(request.as_of_unix_time());
    if (!record) {
      return NotFound("no version was created at or before unix time " +
                      std::to_string(request.as_of_unix_time()));
    }
    if (record->version == latest_version) {
      *snapshot = latest;
      return Status::OK;
    }
  } else {
    if (!latest) return NotFound("no global map version exists yet");
    *snapshot = latest;
    return Status::OK;
  }
  const std::optional<EncodedGrid> grid = store_->GetVersionGrid(record->version);
  if (!grid) {
    return NotFound("the grid of version " + std::to_string(record->version) +
                    " was dropped by the retention setting; its provenance is still listed");
  }
  auto loaded = std::make_shared<GlobalMapSnapshot>();
  loaded->info = *record;
  loaded->encoded = *grid;
  GridDecodeError code;
  std::string error;
  if (!Decompress(*grid, GridLimits(), &loaded->grid, &code, &error)) {
    return Status(StatusCode::DATA_LOSS, "stored version is corrupt: " + error);
  }
  *snapshot = std::move(loaded);
  return Status::OK;
}

Status MapServiceImpl::GetGlobalMap(grpc::ServerContext* /*context*/,
                                    const v1::GetGlobalMapRequest* request,
                                    v1::GlobalMap* response) {
  std::shared_ptr<const GlobalMapSnapshot> snapshot;
  Status status = SelectVersion(*request, &snapshot);
  if (!status.ok()) return status;
  response->set_version(snapshot->info.version);
  response->set_created_unix_time(snapshot->info.created_unix_time);
  const bool native = request->resolution() == 0.0 ||
                      request->resolution() == snapshot->grid.geometry.resolution;
  if (!request->has_bbox() && native) {
    // The whole map as compressed once by the worker: no per-request work.
    ToProto(snapshot->encoded, response->mutable_grid());
    return Status::OK;
  }
  RegionQuery query;
  query.resolution = request->resolution();
  query.max_cells = options_.limits.max_query_cells;
  if (request->has_bbox()) {
    const v1::BoundingBox& b = request->bbox();
    query.box = std::make_pair(Eigen::Vector2d(b.min_x(), b.min_y()),
                               Eigen::Vector2d(b.max_x(), b.max_y()));
  }
  QuantizedGrid region;
  RegionError code;
  std::string error;
  if (!ExtractRegion(snapshot->grid, query, &region, &code, &error)) {
    return Status(code == RegionError::kTooLarge ? StatusCode::RESOURCE_EXHAUSTED
                                                 : StatusCode::INVALID_ARGUMENT,
                  error);
  }
  ToProto(Compress(region), response->mutable_grid());
  return Status::OK;
}

Status MapServiceImpl::ListVersions(grpc::ServerContext* /*context*/,
                                    const v1::ListVersionsRequest* request,
                                    v1::ListVersionsResponse* response) {
  if (request->limit() < 0 || request->limit() > 10000 || request->before_version() < 0) {
    return Status(StatusCode::INVALID_ARGUMENT,
                  "limit must be in [0, 10000] and before_version >= 0");
  }
  const int limit = request->limit() == 0 ? 100 : request->limit();
  for (const VersionRecord& version : store_->ListVersions(limit, request->before_version())) {
    ToProto(version, response->add_versions());
  }
  return Status::OK;
}

Status MapServiceImpl::GetVersion(grpc::ServerContext* /*context*/,
                                  const v1::GetVersionRequest* request,
                                  v1::VersionInfo* response) {
  if (request->version() < 0) {
    return Status(StatusCode::INVALID_ARGUMENT, "version must be >= 0");
  }
  const std::optional<VersionRecord> version = request->version() == 0
                                                   ? store_->LatestVersion()
                                                   : store_->GetVersion(request->version());
  if (!version) {
    return NotFound(request->version() == 0
                        ? std::string("no global map version exists yet")
                        : "version " + std::to_string(request->version()) + " does not exist");
  }
  ToProto(*version, response);
  return Status::OK;
}

Status MapServiceImpl::GetRobots(grpc::ServerContext* /*context*/,
                                 const v1::GetRobotsRequest* request,
                                 v1::GetRobotsResponse* response) {
  std::map<std::string, RobotPlacementRecord> placements;
  for (RobotPlacementRecord& p : worker_->Placements()) placements[p.robot_id] = std::move(p);
  const auto latest = feed_->Latest();
  response->set_latest_version(latest ? latest->info.version : 0);
  for (const RobotRecord& robot : store_->ListRobots()) {
    v1::RobotInfo* info = response->add_robots();
    info->set_robot_id(robot.robot_id);
    info->set_name(robot.name);
    info->set_sensor_description(robot.sensor_description);
    info->set_algorithm(robot.algorithm);
    info->set_registered_unix_time(robot.registered_unix_time);
    RobotPlacementRecord placement;
    placement.robot_id = robot.robot_id;
    placement.source = "unplaced";
    placement.note = "not yet seen by the merge worker";
    if (auto it = placements.find(robot.robot_id); it != placements.end()) placement = it->second;
    ToProto(placement, info->mutable_placement());
    info->set_submap_count(store_->CountSubmapIds(robot.robot_id));
    const std::optional<TrajectoryRecord> trajectory = store_->LatestTrajectory(robot.robot_id);
    info->set_trajectory_revision(trajectory ? trajectory->revision : -1);
    if (!trajectory || !placement.placed || trajectory->poses.empty()) continue;
    const auto to_global = [&](const StampedPose& p) {
      return StampedPose{p.timestamp, placement.local_in_global * p.pose};
    };
    info->set_has_latest_pose(true);
    ToProto(to_global(trajectory->poses.back()), info->mutable_latest_pose_in_global());
    if (request->include_trajectories()) {
      for (const StampedPose& p : trajectory->poses) {
        ToProto(to_global(p), info->add_trajectory_in_global());
      }
    }
  }
  return Status::OK;
}

Status MapServiceImpl::SubscribeMapUpdates(grpc::ServerContext* context,
                                           const v1::SubscribeMapUpdatesRequest* request,
                                           grpc::ServerWriter<v1::MapUpdate>* writer) {
  int64_t last = request->after_version();
  if (last < 0) return Status(StatusCode::INVALID_ARGUMENT, "after_version must be >= 0");
  if (last == 0) {
    // Start with the latest existing version, if any.
    if (const auto latest = feed_->Latest()) last = latest->info.version - 1;
  }
  // Wake up regularly to notice a cancelled client or a stopping server.
  while (!context->IsCancelled() && !feed_->closed()) {
    const auto snapshot = feed_->WaitNewer(last, std::chrono::milliseconds(200));
    if (!snapshot) continue;
    v1::MapUpdate update;
    ToProto(snapshot->info, update.mutable_version());
    if (request->include_grid()) {
      update.mutable_map()->set_version(snapshot->info.version);
      update.mutable_map()->set_created_unix_time(snapshot->info.created_unix_time);
      ToProto(snapshot->encoded, update.mutable_map()->mutable_grid());
    }
    if (!writer->Write(update)) break;  // the client went away
    last = snapshot->info.version;
  }
  return Status::OK;
}

}  // namespace fleetmap
