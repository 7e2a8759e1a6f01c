#ifndef FLEETMAP_MAP_SERVER_SERVER_CONVERSIONS_H_
#define FLEETMAP_MAP_SERVER_SERVER_CONVERSIONS_H_

// The one place where fleetmap.v1 messages meet domain types. FromProto functions validate as
// they convert and return the gRPC status a handler should send when the data is unusable.

#include <grpcpp/grpcpp.h>

#include "map_server/store/records.h"
#include "proto/conversions.h"
#include "proto/fleetmap/v1/fleetmap.pb.h"
#include "shared/codec/grid_codec.h"

namespace fleetmap {

// Limits on what a client may send; beyond them the server answers RESOURCE_EXHAUSTED.
struct UploadLimits {
  GridLimits submap_grid{/*max_side=*/8192, /*max_cells=*/16LL << 20};
  int max_scan_poses = 100000;
  int max_trajectory_poses = 1000000;
  int max_submaps_per_request = 256;
  int max_detections_per_request = 1024;
  int64_t max_query_cells = 64LL << 20;  // cells in one GetGlobalMap answer
};

// Robot ids: 1-64 characters of [A-Za-z0-9_.-].
grpc::Status ValidateRobotId(const std::string& robot_id, const char* field);

grpc::Status FromProto(const v1::RegisterRobotRequest& request, double now, RobotRecord* robot);
grpc::Status FromProto(const std::string& robot_id, const v1::SubmapUpload& upload,
                       const UploadLimits& limits, Submap* submap);
grpc::Status FromProto(const v1::UploadTrajectoryRequest& request, const UploadLimits& limits,
                       double now, TrajectoryRecord* trajectory);
grpc::Status FromProto(const std::string& observer_id, const v1::Detection& detection,
                       double now, DetectionRecord* record);

void ToProto(const RobotPlacementRecord& placement, v1::RobotPlacement* out);
void ToProto(const VersionRecord& version, v1::VersionInfo* out);

// A store outcome as the acknowledgement of one item.
void ToAck(PutOutcome outcome, const std::string& error, v1::ItemAck* ack);
// A store outcome of a unary upload as a status (OK for inserted and duplicate).
grpc::Status ToStatus(PutOutcome outcome, const std::string& what, const std::string& error);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_SERVER_CONVERSIONS_H_
