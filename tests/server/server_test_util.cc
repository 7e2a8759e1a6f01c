#include "tests/server/server_test_util.h"

#include <chrono>
#include <thread>

namespace fleetmap::testing {

OccupancyGrid MakeRoomGrid(int size) {
  OccupancyGrid grid(OccupancyGridOptions(), Eigen::Vector2d::Zero(), size, size);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      grid.SetLogOdds(CellIndex(x, y), y == size - 1 ? 3.0f : -2.0f);
    }
  }
  return grid;
}

v1::SubmapUpload MakeSubmapUpload(int64_t submap_id, int64_t revision,
                                  const Rigid2d& submap_in_local, int size) {
  v1::SubmapUpload upload;
  upload.set_submap_id(submap_id);
  upload.set_revision(revision);
  *upload.mutable_submap_in_local() = ToProto(submap_in_local);
  ToProto(StampedPose{1.0 + submap_id, submap_in_local}, upload.add_scan_poses());
  upload.set_finished(true);
  ToProto(EncodeGrid(MakeRoomGrid(size)), upload.mutable_grid());
  return upload;
}

v1::RegisterRobotRequest MakeRegistration(const std::string& robot_id, bool with_start_pose,
                                          const Rigid2d& local_in_global) {
  v1::RegisterRobotRequest request;
  request.set_robot_id(robot_id);
  request.set_name("robot " + robot_id);
  request.set_algorithm("scan-matching");
  if (with_start_pose) *request.mutable_local_in_global() = ToProto(local_in_global);
  return request;
}

MapServerOptions LoopbackServerOptions(const std::string& dir) {
  MapServerOptions options;
  options.db_path = dir + "/map.db";
  options.listen = "127.0.0.1:0";
  options.merge.min_version_interval = 0.05;
  return options;
}

bool WaitForVersion(v1::MapService::StubInterface* stub, int64_t version, double seconds) {
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int>(seconds * 1e3));
  while (std::chrono::steady_clock::now() < deadline) {
    grpc::ClientContext context;
    v1::GetVersionRequest request;
    v1::VersionInfo info;
    if (stub->GetVersion(&context, request, &info).ok() && info.version() >= version) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace fleetmap::testing
