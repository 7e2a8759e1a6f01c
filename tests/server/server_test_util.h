#ifndef FLEETMAP_TESTS_SERVER_SERVER_TEST_UTIL_H_
#define FLEETMAP_TESTS_SERVER_SERVER_TEST_UTIL_H_

#include <string>

#include "map_server/server/conversions.h"
#include "map_server/server/map_server.h"
#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"
#include "shared/core/occupancy_grid.h"

namespace fleetmap::testing {

// A small submap grid in its own frame: `size` x `size` cells at 5 cm, free inside, with an
// occupied wall along its top row.
OccupancyGrid MakeRoomGrid(int size = 40);

// An upload of MakeRoomGrid at `submap_in_local`.
v1::SubmapUpload MakeSubmapUpload(int64_t submap_id, int64_t revision,
                                  const Rigid2d& submap_in_local = Rigid2d(), int size = 40);

v1::RegisterRobotRequest MakeRegistration(const std::string& robot_id, bool with_start_pose,
                                          const Rigid2d& local_in_global = Rigid2d());

// A server on a free loopback port storing in `dir`/map.db, publishing versions 50 ms apart.
MapServerOptions LoopbackServerOptions(const std::string& dir);

// Polls GetVersion until the latest version is at least `version`; false after `seconds`.
bool WaitForVersion(v1::MapService::StubInterface* stub, int64_t version, double seconds = 10.0);

}  // namespace fleetmap::testing

#endif  // FLEETMAP_TESTS_SERVER_SERVER_TEST_UTIL_H_
