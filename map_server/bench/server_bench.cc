// fleetmap-server-bench: submap ingest with concurrent uploaders and global map queries,
// against a real server listening on 127.0.0.1 (started in this process unless --server).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <random>
#include <thread>

#include <CLI/CLI.hpp>

#include "map_server/server/map_server.h"

namespace fleetmap {
namespace {

using Clock = std::chrono::steady_clock;

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(p * values.size()));
  return values[index];
}

// A 10 m x 10 m submap at 5 cm: free floor, walls around, a few random boxes.
v1::Grid MakeSubmapGrid(int seed) {
  const int n = 200;
  OccupancyGrid grid(OccupancyGridOptions(), Eigen::Vector2d::Zero(), n, n);
  std::mt19937 random(static_cast<unsigned>(seed));
  std::uniform_int_distribution<int> pick(10, n - 30);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const bool wall = x < 2 || y < 2 || x >= n - 2 || y >= n - 2;
      grid.SetLogOdds(CellIndex(x, y), wall ? 3.5f : -1.5f);
    }
  }
  for (int b = 0; b < 6; ++b) {
    const int bx = pick(random), by = pick(random);
    for (int y = by; y < by + 15; ++y) {
      for (int x = bx; x < bx + 15; ++x) grid.SetLogOdds(CellIndex(x, y), 3.5f);
    }
  }
  v1::Grid out;
  ToProto(EncodeGrid(grid), &out);
  return out;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) {
  using namespace fleetmap;
  int uploaders = 8;
  double duration = 10.0;
  int queries = 100;
  std::string server_address;
  std::string db_path;
  CLI::App app{"fleetmap server benchmark: ingest and global map queries on loopback"};
  app.add_option("--uploaders", uploaders, "concurrent uploading robots")->capture_default_str();
  app.add_option("--duration", duration, "seconds of ingest")->capture_default_str();
  app.add_option("--queries", queries, "GetGlobalMap calls per query kind")->capture_default_str();
  app.add_option("--server", server_address, "use a running server instead of starting one");
  app.add_option("--db", db_path, "database of the in-process server (default: a temp file)");
  CLI11_PARSE(app, argc, argv);

  std::unique_ptr<MapServer> server;
  std::string temp_dir;
  if (server_address.empty()) {
    MapServerOptions options;
    if (db_path.empty()) {
      temp_dir = std::filesystem::temp_directory_path() / ("fleetmap_bench_" + std::to_string(getpid()));
      std::filesystem::create_directories(temp_dir);
      db_path = temp_dir + "/bench.db";
    }
    options.db_path = db_path;
    options.listen = "127.0.0.1:0";
    std::string error;
    server = MapServer::Start(options, &error);
    if (!server) {
      std::cerr << "fleetmap-server-bench: " << error << "\n";
      return 1;
    }
    server_address = server->address();
  }
  std::cout << "server " << server_address << " (db " << db_path << "), " << uploaders
            << " uploaders, " << duration << " s" << std::endl;

  // 8 robots in rows 12.5 m apart, each cycling over 10 submap spots 9 m apart: 100 m x 100 m.
  std::vector<std::vector<double>> latencies(static_cast<size_t>(uploaders));
  std::atomic<int64_t> failures{0};
  const auto start = Clock::now();
  const auto stop_at = start + std::chrono::milliseconds(static_cast<int>(duration * 1000));
  std::vector<std::thread> threads;
  for (int u = 0; u < uploaders; ++u) {
    threads.emplace_back([&, u] {
      auto stub = v1::MapService::NewStub(MakeClientChannel(server_address));
      const std::string robot = "bench-" + std::to_string(u);
      v1::RegisterRobotRequest registration;
      registration.set_robot_id(robot);
      *registration.mutable_local_in_global() = ToProto(Rigid2d(0.0, 12.5 * u, 0.0));
      grpc::ClientContext register_context;
      v1::RegisterRobotResponse registered;
      if (!stub->RegisterRobot(&register_context, registration, &registered).ok()) {
        ++failures;
        return;
      }
      v1::UploadSubmapsRequest request;
      request.set_robot_id(robot);
      v1::SubmapUpload* upload = request.add_submaps();
      *upload->mutable_grid() = MakeSubmapGrid(u);
      upload->set_finished(true);
      for (int64_t id = 0; Clock::now() < stop_at; ++id) {
        upload->set_submap_id(id);
        *upload->mutable_submap_in_local() = ToProto(Rigid2d(9.0 * (id % 10), 0.0, 0.0));
        grpc::ClientContext context;
        v1::UploadSubmapsResponse response;
        const auto t0 = Clock::now();
        const grpc::Status status = stub->UploadSubmaps(&context, request, &response);
        latencies[static_cast<size_t>(u)].push_back(Ms(Clock::now() - t0));
        if (!status.ok() || response.acks(0).code() != 0) ++failures;
      }
    });
  }
  for (auto& t : threads) t.join();
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  std::vector<double> all;
  for (const auto& l : latencies) all.insert(all.end(), l.begin(), l.end());
  std::printf("ingest: %zu submaps in %.2f s = %.0f submaps/s; ack latency p50 %.2f ms, p99 %.2f "
              "ms, max %.2f ms; %lld failures\n",
              all.size(), elapsed, all.size() / elapsed, Percentile(all, 0.5),
              Percentile(all, 0.99), Percentile(all, 1.0), static_cast<long long>(failures));

  // Let the merge worker fold in the last uploads.
  auto stub = v1::MapService::NewStub(MakeClientChannel(server_address));
  // Wait until the merge worker has folded everything in: the version stops changing.
  const auto wait_start = Clock::now();
  int64_t seen = -1;
  for (int stable = 0; stable < 20 && Clock::now() - wait_start < std::chrono::seconds(120);) {
    grpc::ClientContext context;
    v1::VersionInfo info;
    const int64_t v = stub->GetVersion(&context, v1::GetVersionRequest(), &info).ok() ? info.version() : 0;
    stable = (v == seen && v > 0) ? stable + 1 : 0;
    seen = v;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::printf("merge worker caught up %.1f s after ingest ended (version %lld)\n",
              std::chrono::duration<double>(Clock::now() - wait_start).count() - 2.0,
              static_cast<long long>(seen));
  const auto run_queries = [&](const char* label, const v1::GetGlobalMapRequest& request) {
    std::vector<double> times;
    v1::GlobalMap map;
    for (int i = 0; i < queries; ++i) {
      grpc::ClientContext context;
      const auto t0 = Clock::now();
      const grpc::Status status = stub->GetGlobalMap(&context, request, &map);
      times.push_back(Ms(Clock::now() - t0));
      if (!status.ok()) {
        std::cerr << label << ": " << status.error_message() << "\n";
        return;
      }
    }
    std::printf("%s: version %lld, %d x %d cells (%.1f M), %.2f MB compressed; p50 %.2f ms, p99 "
                "%.2f ms\n",
                label, static_cast<long long>(map.version()), map.grid().width(),
                map.grid().height(), map.grid().width() * 1e-6 * map.grid().height(),
                map.grid().cells_zstd().size() / 1e6, Percentile(times, 0.5),
                Percentile(times, 0.99));
  };
  run_queries("get-global-map whole (cached)", v1::GetGlobalMapRequest());
  v1::GetGlobalMapRequest box;
  box.mutable_bbox()->set_min_x(0.0);
  box.mutable_bbox()->set_min_y(0.0);
  box.mutable_bbox()->set_max_x(100.0);
  box.mutable_bbox()->set_max_y(100.0);
  run_queries("get-global-map bbox 100x100 m (crop+compress)", box);
  box.set_resolution(0.2);
  run_queries("get-global-map bbox 100x100 m at 0.2 m", box);
  if (server) server->Shutdown();
  if (!temp_dir.empty()) std::filesystem::remove_all(temp_dir);
  return failures == 0 ? 0 : 1;
}
