// fleetmap-log: look inside a CARMEN log and turn its raw odometry into a map.
//
//   fleetmap-log info LOG
//   fleetmap-log map LOG --out DIR          (DIR/map.pgm, map.yaml, map.png, trajectory.txt)
//   fleetmap-log trajectory LOG --out T.txt (one line per laser scan: ipc_timestamp x y theta)

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include "shared/io/carmen_reader.h"
#include "shared/io/carmen_trajectory.h"
#include "shared/io/trajectory_file.h"
#include "shared/tools/log_summary.h"
#include "shared/tools/odometry_map.h"

namespace fleetmap {
namespace {

int Fail(const std::string& message) {
  std::fprintf(stderr, "fleetmap-log: error: %s\n", message.c_str());
  return 1;
}

// Progress on stderr, so stdout stays the report.
std::function<void(long)> ProgressPrinter(bool quiet) {
  if (quiet) return {};
  const auto start = std::chrono::steady_clock::now();
  return [start](long scans) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "  %ld scans read (%.1f s)\n", scans, seconds);
  };
}

void AddReaderOptions(CLI::App* command, CarmenReaderOptions* options) {
  command->add_flag("--skip-bad-lines", options->skip_bad_lines,
                    "Count and skip malformed lines instead of stopping at the first");
  command
      ->add_option("--max-range", options->max_range,
                   "Readings at or above this (m) are no-returns; a PARAM "
                   "robot_front_laser_max in the log overrides it")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
}

int RunInfo(const std::string& log, const CarmenReaderOptions& options, bool all_params,
            bool quiet) {
  LogSummary summary;
  std::string error;
  if (!SummarizeLog(log, options, &summary, &error, ProgressPrinter(quiet))) return Fail(error);
  PrintLogSummary(summary, all_params ? -1 : 20, std::cout);
  if (summary.laser_scans == 0 && summary.odometry_records == 0 && summary.params.empty()) {
    std::fprintf(stderr,
                 "fleetmap-log: warning: no FLASER, ROBOTLASER1, ODOM or PARAM lines: "
                 "is %s a CARMEN log?\n",
                 log.c_str());
  }
  return 0;
}

int RunMap(const std::string& log, const std::string& out_dir,
           const CarmenReaderOptions& reader_options, const OdometryMapOptions& map_options,
           bool quiet) {
  OccupancyGrid grid;
  Trajectory trajectory;
  std::string error;
  if (!quiet) std::fprintf(stderr, "fleetmap-log: building a map from %s\n", log.c_str());
  if (!BuildOdometryMap(log, reader_options, map_options, &grid, &trajectory, &error,
                        ProgressPrinter(quiet))) {
    return Fail(error);
  }
  if (trajectory.empty()) return Fail(log + ": no laser scans (FLASER/ROBOTLASER1) in the log");
  if (!WriteOdometryMapOutputs(out_dir, grid, trajectory, &error)) return Fail(error);
  std::printf(
      "%zu scans; %d x %d cells at %.3f m; wrote %s/map.pgm, map.yaml, map.png, "
      "trajectory.txt\n",
      trajectory.size(), grid.width(), grid.height(), grid.resolution(), out_dir.c_str());
  return 0;
}

int RunTrajectory(const std::string& log, const std::string& out,
                  const CarmenReaderOptions& options) {
  Trajectory trajectory;
  std::string error;
  if (!ReadOdometryTrajectory(log, options, &trajectory, &error)) return Fail(error);
  if (!WriteTrajectory(out, trajectory, &error)) return Fail(error);
  std::printf("%zu poses written to %s\n", trajectory.size(), out.c_str());
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{
      "fleetmap-log: inspect CARMEN laser logs (.clf/.log, plain, .gz or .bz2) and build maps "
      "from their raw odometry."};
  app.require_subcommand(1);
  std::string log;
  std::string out;
  bool quiet = false;
  bool all_params = false;
  CarmenReaderOptions reader_options;
  OdometryMapOptions map_options;

  CLI::App* info = app.add_subcommand("info",
                                      "Print what the log holds: message counts, beams "
                                      "per scan, time span, distance, params");
  info->add_option("log,--log", log, "CARMEN log")->required()->check(CLI::ExistingFile);
  info->add_flag("--all-params", all_params, "Print every PARAM (default: the first 20)");
  info->add_flag("-q,--quiet", quiet, "No progress output");
  AddReaderOptions(info, &reader_options);

  CLI::App* map = app.add_subcommand(
      "map",
      "Write DIR/map.pgm + map.yaml + map.png and DIR/trajectory.txt, inserting every "
      "scan at its raw-odometry pose");
  map->add_option("log,--log", log, "CARMEN log")->required()->check(CLI::ExistingFile);
  map->add_option("-o,--out", out, "Output directory (created)")->required();
  map->add_option("--resolution", map_options.grid.resolution, "Cell size (m)")
      ->capture_default_str()
      ->check(CLI::Range(0.005, 10.0));
  map->add_option("--max-trace-range", map_options.grid.max_trace_range,
                  "Trace beams at most this far (m); 0: up to the scan's max range")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  map->add_option("--stride", map_options.scan_stride, "Insert every n-th scan")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  map->add_flag("-q,--quiet", quiet, "No progress output");
  AddReaderOptions(map, &reader_options);

  CLI::App* trajectory =
      app.add_subcommand("trajectory",
                         "Write the raw-odometry trajectory, one line per laser scan: "
                         "ipc_timestamp x y theta");
  trajectory->add_option("log,--log", log, "CARMEN log")->required()->check(CLI::ExistingFile);
  trajectory->add_option("-o,--out", out, "Trajectory file to write")->required();
  AddReaderOptions(trajectory, &reader_options);

  CLI11_PARSE(app, argc, argv);
  if (info->parsed()) return RunInfo(log, reader_options, all_params, quiet);
  if (map->parsed()) return RunMap(log, out, reader_options, map_options, quiet);
  return RunTrajectory(log, out, reader_options);
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }
