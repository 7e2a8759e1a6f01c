#ifndef FLEETMAP_PROTO_CONVERSIONS_H_
#define FLEETMAP_PROTO_CONVERSIONS_H_

// Conversions between fleetmap.v1 messages and the shared domain types that both sides of the
// API use (poses, stamped poses, encoded grids). Server-side validation and agent-side message
// assembly build on these; no other code converts these types.

#include "proto/fleetmap/v1/fleetmap.pb.h"
#include "shared/codec/grid_codec.h"
#include "shared/core/rigid2d.h"
#include "shared/core/trajectory.h"

namespace fleetmap {

Rigid2d FromProto(const v1::Pose2d& pose);
v1::Pose2d ToProto(const Rigid2d& pose);
void ToProto(const StampedPose& pose, v1::StampedPose* out);

// An unknown cell encoding becomes one the grid decoder refuses, so corrupt messages fail there.
EncodedGrid FromProto(const v1::Grid& grid);
void ToProto(const EncodedGrid& grid, v1::Grid* out);

}  // namespace fleetmap

#endif  // FLEETMAP_PROTO_CONVERSIONS_H_
