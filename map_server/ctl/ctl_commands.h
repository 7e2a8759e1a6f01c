#ifndef FLEETMAP_MAP_SERVER_CTL_CTL_COMMANDS_H_
#define FLEETMAP_MAP_SERVER_CTL_CTL_COMMANDS_H_

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "proto/fleetmap/v1/fleetmap.grpc.pb.h"

namespace fleetmap {

// What every fleetmapctl command needs. Commands print human-readable text, or JSON with
// `json`, to `out`; errors go to stderr; each returns the process exit code.
struct CtlContext {
  v1::MapService::StubInterface* stub = nullptr;
  bool json = false;
  double timeout_seconds = 30.0;
  std::ostream* out = nullptr;
};

struct ExportOptions {
  std::string stem;              // writes <stem>.pgm, <stem>.yaml and <stem>.png
  int64_t version = 0;           // 0 = latest
  double as_of_unix_time = 0.0;  // > 0: newest version at or before
  std::vector<double> bbox;      // empty, or min_x min_y max_x max_y
  double resolution = 0.0;       // 0 = native
};

int RunRobots(const CtlContext& context, bool with_trajectories);
int RunExport(const CtlContext& context, const ExportOptions& options);
int RunHistory(const CtlContext& context, int limit);
int RunShow(const CtlContext& context, int64_t version);
int RunDiff(const CtlContext& context, int64_t before, int64_t after, const std::string& png);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_CTL_CTL_COMMANDS_H_
