#ifndef FLEETMAP_ROBOT_AGENT_AGENT_PROTO_CONVERSIONS_H_
#define FLEETMAP_ROBOT_AGENT_AGENT_PROTO_CONVERSIONS_H_

// The agent's one place where domain types meet fleetmap.v1 messages.

#include <string>

#include "proto/conversions.h"
#include "proto/fleetmap/v1/fleetmap.pb.h"
#include "robot_agent/localization/pose_density.h"
#include "shared/codec/grid_codec.h"
#include "shared/core/robot_detection.h"
#include "shared/core/submap.h"
#include "shared/core/trajectory.h"

namespace fleetmap::agent {

// Poses and grids convert with the shared proto/conversions.h; these are the agent's messages.
using fleetmap::FromProto;
using fleetmap::ToProto;

// The submap with its grid cropped to observed cells, int8 log-odds, zstd.
v1::SubmapUpload ToProto(const Submap& submap, int zstd_level = 1);
v1::UploadTrajectoryRequest ToTrajectoryRequest(const std::string& robot_id, int64_t revision,
                                                const Trajectory& trajectory);
v1::Detection ToProto(const RobotDetection& detection, int64_t detection_id);
// Collaborative localization. FromProto is false for a density the filter cannot use (no
// kernels, a weight or covariance out of range).
v1::PoseDensity ToProto(const PoseDensity& density);
bool FromProto(const v1::PoseDensity& message, PoseDensity* density);

}  // namespace fleetmap::agent

#endif  // FLEETMAP_ROBOT_AGENT_AGENT_PROTO_CONVERSIONS_H_
