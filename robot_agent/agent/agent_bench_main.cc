// fleetmap-agent-bench: how fast the robot's outbox takes items, and (with --server) how fast
// the uploader empties it into a running server.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "robot_agent/agent/outbox.h"
#include "robot_agent/agent/proto_conversions.h"
#include "robot_agent/agent/uploader.h"
#include "shared/core/submap.h"

namespace {

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A 10 m x 10 m submap at 5 cm with a square room's walls, like a finished local submap.
std::string SubmapPayload(int64_t id) {
  fleetmap::Submap submap;
  submap.submap_id = id;
  submap.revision = 1;
  submap.finished = true;
  for (int y = 0; y < 200; ++y) {
    for (int x = 0; x < 200; ++x) {
      const bool wall = x == 0 || y == 0 || x == 199 || y == 199;
      submap.grid.SetLogOdds({x, y}, wall ? 3.0f : -2.0f);
    }
  }
  for (int i = 0; i < 100; ++i) submap.scan_poses.push_back({0.1 * i, fleetmap::Rigid2d()});
  return fleetmap::agent::ToProto(submap).SerializeAsString();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fleetmap-agent-bench: outbox enqueue rate and upload throughput"};
  int items = 500;
  std::string dir = std::filesystem::temp_directory_path().string();
  std::string server;
  app.add_option("--items", items, "submaps to queue")->check(CLI::Range(1, 1000000));
  app.add_option("--dir", dir, "folder for the temporary outbox");
  app.add_option("--server", server, "also upload to this running fleetmap-server (host:port)");
  CLI11_PARSE(app, argc, argv);

  const std::string path = dir + "/fleetmap-agent-bench-" + std::to_string(::getpid()) + ".db";
  std::string error;
  auto outbox = fleetmap::Outbox::Open(path, &error);
  if (!outbox) {
    std::fprintf(stderr, "fleetmap-agent-bench: %s\n", error.c_str());
    return 1;
  }
  const std::string payload = SubmapPayload(0);
  std::printf("submap payload: %zu bytes (10 m x 10 m at 5 cm, zstd)\n", payload.size());
  auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < items; ++i) {
    bool inserted;
    if (!outbox->Enqueue({"bench", fleetmap::OutboxKind::kSubmap, i, 1}, payload, 0.0, true,
                         &inserted, &error)) {
      std::fprintf(stderr, "fleetmap-agent-bench: %s\n", error.c_str());
      return 1;
    }
  }
  const double enqueue = Seconds(start);
  std::printf("enqueue (WAL, synchronous=FULL): %d items in %.3f s = %.0f items/s\n", items,
              enqueue, items / enqueue);
  if (!server.empty()) {
    fleetmap::v1::RegisterRobotRequest registration;
    registration.set_robot_id("bench-" + std::to_string(::getpid()));
    // Re-key the queued items to this robot id by queuing afresh.
    auto upload_outbox = fleetmap::Outbox::Open(path + ".upload", &error);
    if (!upload_outbox) {
      std::fprintf(stderr, "fleetmap-agent-bench: %s\n", error.c_str());
      return 1;
    }
    for (int i = 0; i < items; ++i) {
      bool inserted;
      upload_outbox->Enqueue({registration.robot_id(), fleetmap::OutboxKind::kSubmap, i, 1},
                             payload, 0.0, true, &inserted, &error);
    }
    fleetmap::Uploader uploader(fleetmap::UploaderOptions(), upload_outbox.get(),
                                grpc::CreateChannel(server, grpc::InsecureChannelCredentials()),
                                registration);
    start = std::chrono::steady_clock::now();
    uploader.Start();
    const bool drained = uploader.WaitUntilEmpty(600.0);
    const double upload = Seconds(start);
    uploader.Stop();
    std::printf("upload to %s: %d submaps in %.3f s = %.0f submaps/s%s\n", server.c_str(), items,
                upload, items / upload, drained ? "" : " (NOT drained)");
    upload_outbox.reset();
    for (const char* suffix : {"", "-wal", "-shm"}) {
      std::filesystem::remove(path + ".upload" + suffix);
    }
  }
  outbox.reset();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  return 0;
}
