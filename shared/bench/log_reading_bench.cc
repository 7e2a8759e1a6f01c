// Measures how fast CarmenReader streams the public benchmark logs (decompression + parsing),
// in seconds per 10,000 laser scans: best of N runs, wall clock and CPU time (CPU time is less
// sensitive to other work on a shared machine), plus the CPU time of decompressing and
// splitting lines alone. Not a test: it prints figures for docs/BENCHMARKS.md.
//
//   log_reading_bench [--data-dir DIR] [--repeat N] [LOG...]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "shared/io/carmen_reader.h"
#include "shared/io/decompressing_stream.h"

namespace fleetmap {
namespace {

struct Timing {
  long lasers = 0;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;
  double decompress_cpu_seconds = 0.0;
};

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

bool ReadOnce(const std::string& path, Timing* timing, std::string* error) {
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = CpuSeconds();
  auto reader = CarmenReader::Open(path, CarmenReaderOptions(), error);
  if (!reader) return false;
  CarmenRecord record;
  timing->lasers = 0;
  while (reader->Next(&record)) {
    if (std::holds_alternative<LaserRecord>(record)) ++timing->lasers;
  }
  if (!reader->error().empty()) {
    *error = reader->error();
    return false;
  }
  timing->cpu_seconds = CpuSeconds() - cpu_start;
  timing->wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  const double decompress_start = CpuSeconds();
  auto stream = DecompressingStream::Open(path, error);
  if (!stream) return false;
  std::string_view line;
  while (stream->NextLine(&line)) {
  }
  timing->decompress_cpu_seconds = CpuSeconds() - decompress_start;
  return stream->error().empty();
}

std::vector<std::string> DefaultLogs(const std::string& data_dir) {
  std::vector<std::string> logs;
  for (const char* relative :
       {"intel-lab/intel.clf.bz2", "aces/aces.clf.bz2", "fr079/fr079.clf.bz2",
        "mit-csail/mit-csail.clf.bz2", "fr-clinic/fr-clinic_robotlaser.clf.bz2",
        "mit-killian/mit-killian_from-mola-rawlog.clf.gz"}) {
    const std::string path = data_dir + "/" + relative;
    if (std::filesystem::exists(path)) logs.push_back(path);
  }
  return logs;
}

int Run(int argc, char** argv) {
  CLI::App app{"Times CarmenReader on CARMEN logs: seconds per 10,000 laser scans (best of N)."};
  std::string data_dir = "../shared/data";
  int repeat = 3;
  std::vector<std::string> logs;
  app.add_option("--data-dir", data_dir, "Folder of the public data sets (used without LOGs)")
      ->capture_default_str();
  app.add_option("--repeat", repeat, "Runs per log; the fastest counts")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  app.add_option("logs", logs, "Logs to read (default: the benchmark logs in --data-dir)");
  CLI11_PARSE(app, argc, argv);
  if (logs.empty()) logs = DefaultLogs(data_dir);
  if (logs.empty()) {
    std::fprintf(stderr, "log_reading_bench: error: no logs given and none in %s\n",
                 data_dir.c_str());
    return 1;
  }

  std::printf("%-38s %6s %6s %7s %7s %10s %10s %11s\n", "log", "scans", "MB", "wall s", "cpu s",
              "wall/10k", "cpu/10k", "unzip cpu s");
  for (const std::string& path : logs) {
    Timing best;
    for (int i = 0; i < repeat; ++i) {
      Timing timing;
      std::string error;
      if (!ReadOnce(path, &timing, &error)) {
        std::fprintf(stderr, "log_reading_bench: error: %s\n", error.c_str());
        return 1;
      }
      best.lasers = timing.lasers;
      best.wall_seconds =
          i == 0 ? timing.wall_seconds : std::min(best.wall_seconds, timing.wall_seconds);
      best.cpu_seconds =
          i == 0 ? timing.cpu_seconds : std::min(best.cpu_seconds, timing.cpu_seconds);
      best.decompress_cpu_seconds =
          i == 0 ? timing.decompress_cpu_seconds
                 : std::min(best.decompress_cpu_seconds, timing.decompress_cpu_seconds);
    }
    const double megabytes = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
    const double scale = best.lasers > 0 ? 10000.0 / static_cast<double>(best.lasers) : 0.0;
    std::printf("%-38s %6ld %6.2f %7.3f %7.3f %10.3f %10.3f %11.3f\n",
                std::filesystem::path(path).filename().c_str(), best.lasers, megabytes,
                best.wall_seconds, best.cpu_seconds, best.wall_seconds * scale,
                best.cpu_seconds * scale, best.decompress_cpu_seconds);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }
