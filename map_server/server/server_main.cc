// fleetmap-server: the central map server (gRPC API fleetmap.v1 over an SQLite database).
#include <csignal>
#include <fstream>
#include <iostream>

#include <CLI/CLI.hpp>

#include "map_server/server/map_server.h"

int main(int argc, char** argv) {
  fleetmap::MapServerOptions options;
  std::string port_file;
  double version_interval = options.merge.min_version_interval;
  CLI::App app{"fleetmap map server: stores robot uploads and serves the versioned global map"};
  app.add_option("--db", options.db_path, "SQLite database file (created when missing)")
      ->required();
  app.add_option("--listen", options.listen, "address to listen on, host:port (port 0: any)")
      ->capture_default_str();
  app.add_option("--keep-versions", options.retention.keep_version_grids,
                 "keep the grids of this many newest versions (0 = all); older versions keep "
                 "their provenance")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--version-interval", version_interval,
                 "seconds between global map versions while uploads arrive")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--resolution", options.merge.resolution, "global map resolution, metres")
      ->check(CLI::Range(0.005, 10.0))
      ->capture_default_str();
  app.add_option("--merge-worker", options.merge_worker,
                 "engine: align robots of unknown start (detections, submap matching); "
                 "known-pose: only robots registered with a start pose are placed")
      ->check(CLI::IsMember({"engine", "known-pose"}))
      ->capture_default_str();
  app.add_option("--settle-seconds", options.settle_seconds,
                 "engine worker: once no submap, detection or robot has come for this long, "
                 "rebuild the merge from the store with everything at once, kept when it places "
                 "at least as many robots (0: never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--merge-threads", options.merge_engine.search_threads,
                 "engine worker: threads for a merge update's searches that do not depend on "
                 "each other; the merged map is the same for any count (0: one per core, at "
                 "most an update's nearby searches)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_flag("--fsync", options.fsync_every_commit,
               "fsync every commit (survives power loss; default survives process crashes)");
  app.add_option("--port-file", port_file, "write the port actually listened on to this file");
  CLI11_PARSE(app, argc, argv);
  options.merge.min_version_interval = version_interval;

  // Block the stop signals before any thread starts, then wait for them on this thread.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  std::string error;
  std::cout << "fleetmap-server: opening " << options.db_path << std::endl;
  auto server = fleetmap::MapServer::Start(options, &error);
  if (!server) {
    std::cerr << "fleetmap-server: " << error << std::endl;
    return 1;
  }
  std::cout << "fleetmap-server: listening on " << server->address() << std::endl;
  if (!port_file.empty()) {
    // Written to a temporary name and renamed, so readers never see a partial file.
    const std::string temporary = port_file + ".tmp";
    std::ofstream(temporary) << server->port() << "\n";
    std::rename(temporary.c_str(), port_file.c_str());
  }
  int signal_number = 0;
  sigwait(&signals, &signal_number);
  std::cout << "fleetmap-server: " << (signal_number == SIGINT ? "SIGINT" : "SIGTERM")
            << " received, shutting down" << std::endl;
  server->Shutdown();
  std::cout << "fleetmap-server: stopped cleanly" << std::endl;
  return 0;
}
