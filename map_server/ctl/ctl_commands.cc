#include "map_server/ctl/ctl_commands.h"

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <google/protobuf/util/json_util.h>

#include "map_server/ctl/map_diff.h"
#include "map_server/server/conversions.h"
#include "shared/io/map_file.h"

namespace fleetmap {
namespace {

void SetDeadline(const CtlContext& context, grpc::ClientContext* rpc) {
  rpc->set_deadline(std::chrono::system_clock::now() +
                    std::chrono::milliseconds(static_cast<int64_t>(context.timeout_seconds * 1e3)));
}

int Fail(const grpc::Status& status, const std::string& what) {
  static const char* kNames[] = {"OK", "CANCELLED", "UNKNOWN", "INVALID_ARGUMENT",
                                 "DEADLINE_EXCEEDED", "NOT_FOUND", "ALREADY_EXISTS",
                                 "PERMISSION_DENIED", "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION",
                                 "ABORTED", "OUT_OF_RANGE", "UNIMPLEMENTED", "INTERNAL",
                                 "UNAVAILABLE", "DATA_LOSS", "UNAUTHENTICATED"};
  const int code = static_cast<int>(status.error_code());
  std::cerr << "fleetmapctl: " << what << " failed: "
            << (code >= 0 && code <= 16 ? kNames[code] : "error") << ": "
            << status.error_message() << "\n";
  return 1;
}

int PrintJson(const CtlContext& context, const google::protobuf::Message& message) {
  std::string json;
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  if (!google::protobuf::util::MessageToJsonString(message, &json, options).ok()) {
    std::cerr << "fleetmapctl: cannot format the answer as JSON\n";
    return 1;
  }
  *context.out << json;
  return 0;
}

std::string FormatTime(double unix_time) {
  const std::time_t seconds = static_cast<std::time_t>(unix_time);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  std::ostringstream out;
  out << std::put_time(&tm, "%Y-%m-%d %H:%M:%S") << " UTC";
  return out.str();
}

std::string FormatPose(const v1::Pose2d& p) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << "(" << p.x() << ", " << p.y() << ", "
      << p.theta() << " rad)";
  return out.str();
}

void PrintVersion(std::ostream& out, const v1::VersionInfo& v, bool detailed) {
  const v1::Provenance& p = v.provenance();
  out << "version " << v.version() << "  " << FormatTime(v.created_unix_time()) << "  "
      << p.trigger() << "  +" << p.new_submaps_size() << " submaps, +"
      << p.new_detections_size() << " detections  " << v.width() << "x" << v.height()
      << " cells" << (v.grid_available() ? "" : " (grid pruned)") << "\n";
  if (!detailed) return;
  out << "  merge engine: " << p.merge_engine() << "\n  triggered by:";
  for (const std::string& id : p.trigger_robot_ids()) out << " " << id;
  out << "\n  grid: " << v.width() << " x " << v.height() << " at " << v.resolution()
      << " m, origin (" << v.origin_x() << ", " << v.origin_y() << ")\n  quality:";
  std::map<std::string, double> quality(p.quality().begin(), p.quality().end());
  for (const auto& [name, value] : quality) out << " " << name << "=" << value;
  out << "\n  placements:\n";
  for (const v1::RobotPlacement& r : v.placements()) {
    out << "    " << r.robot_id() << ": "
        << (r.placed() ? FormatPose(r.local_in_global()) : std::string("unplaced"))
        << (r.placed() && r.has_start_in_global()
                ? ", started at " + FormatPose(r.start_in_global())
                : "")
        << " [" << r.source() << "]" << (r.note().empty() ? "" : " " + r.note()) << "\n";
  }
  out << "  new submaps:";
  for (const auto& s : p.new_submaps()) {
    out << " " << s.robot_id() << "/" << s.submap_id() << "@" << s.revision();
  }
  out << "\n  new detections:";
  for (const auto& d : p.new_detections()) out << " " << d.observer_id() << "#" << d.detection_id();
  out << "\n";
}

// Fetches a map version and decodes its cells.
grpc::Status FetchMap(const CtlContext& context, const v1::GetGlobalMapRequest& request,
                      v1::GlobalMap* map, QuantizedGrid* grid) {
  grpc::ClientContext rpc;
  SetDeadline(context, &rpc);
  grpc::Status status = context.stub->GetGlobalMap(&rpc, request, map);
  if (!status.ok()) return status;
  GridDecodeError code;
  std::string error;
  if (!Decompress(FromProto(map->grid()), GridLimits(), grid, &code, &error)) {
    return grpc::Status(grpc::StatusCode::DATA_LOSS, "the server sent a bad grid: " + error);
  }
  return grpc::Status::OK;
}

}  // namespace

int RunRobots(const CtlContext& context, bool with_trajectories) {
  v1::GetRobotsRequest request;
  request.set_include_trajectories(with_trajectories);
  v1::GetRobotsResponse response;
  grpc::ClientContext rpc;
  SetDeadline(context, &rpc);
  const grpc::Status status = context.stub->GetRobots(&rpc, request, &response);
  if (!status.ok()) return Fail(status, "robots");
  if (context.json) return PrintJson(context, response);
  std::ostream& out = *context.out;
  out << response.robots_size() << " robots, latest version " << response.latest_version()
      << "\n";
  for (const v1::RobotInfo& r : response.robots()) {
    out << r.robot_id() << "  \"" << r.name() << "\"  " << r.algorithm() << "  "
        << r.submap_count() << " submaps  ";
    if (r.placement().placed()) {
      out << "placed " << FormatPose(r.placement().local_in_global()) << " ["
          << r.placement().source() << "]";
      if (r.placement().has_start_in_global()) {
        out << "  started at " << FormatPose(r.placement().start_in_global());
      }
    } else {
      out << "UNPLACED (" << r.placement().note() << ")";
    }
    if (r.has_latest_pose()) out << "  pose " << FormatPose(r.latest_pose_in_global().pose());
    out << "\n";
  }
  return 0;
}

int RunExport(const CtlContext& context, const ExportOptions& options) {
  v1::GetGlobalMapRequest request;
  request.set_version(options.version);
  request.set_as_of_unix_time(options.as_of_unix_time);
  request.set_resolution(options.resolution);
  if (options.bbox.size() == 4) {
    request.mutable_bbox()->set_min_x(options.bbox[0]);
    request.mutable_bbox()->set_min_y(options.bbox[1]);
    request.mutable_bbox()->set_max_x(options.bbox[2]);
    request.mutable_bbox()->set_max_y(options.bbox[3]);
  }
  v1::GlobalMap map;
  QuantizedGrid grid;
  const grpc::Status status = FetchMap(context, request, &map, &grid);
  if (!status.ok()) return Fail(status, "export");
  const OccupancyGrid occupancy = Dequantize(grid);
  std::string error;
  if (!WriteMap(options.stem, occupancy, &error, /*crop=*/false) ||
      !WriteMapPng(options.stem + ".png", occupancy, &error, /*crop=*/false)) {
    std::cerr << "fleetmapctl: export failed: " << error << "\n";
    return 1;
  }
  if (context.json) {
    *context.out << "{\"version\": " << map.version() << ", \"width\": " << grid.geometry.width
                 << ", \"height\": " << grid.geometry.height
                 << ", \"resolution\": " << grid.geometry.resolution << ", \"files\": [\""
                 << options.stem << ".pgm\", \"" << options.stem << ".yaml\", \""
                 << options.stem << ".png\"]}\n";
  } else {
    *context.out << "exported version " << map.version() << " (" << grid.geometry.width << " x "
                 << grid.geometry.height << " cells at " << grid.geometry.resolution
                 << " m) to " << options.stem << ".pgm/.yaml/.png\n";
  }
  return 0;
}

int RunHistory(const CtlContext& context, int limit) {
  v1::ListVersionsRequest request;
  request.set_limit(limit);
  v1::ListVersionsResponse response;
  grpc::ClientContext rpc;
  SetDeadline(context, &rpc);
  const grpc::Status status = context.stub->ListVersions(&rpc, request, &response);
  if (!status.ok()) return Fail(status, "history");
  if (context.json) return PrintJson(context, response);
  if (response.versions().empty()) *context.out << "no versions yet\n";
  for (const v1::VersionInfo& v : response.versions()) PrintVersion(*context.out, v, false);
  return 0;
}

int RunShow(const CtlContext& context, int64_t version) {
  v1::GetVersionRequest request;
  request.set_version(version);
  v1::VersionInfo response;
  grpc::ClientContext rpc;
  SetDeadline(context, &rpc);
  const grpc::Status status = context.stub->GetVersion(&rpc, request, &response);
  if (!status.ok()) return Fail(status, "show");
  if (context.json) return PrintJson(context, response);
  PrintVersion(*context.out, response, true);
  return 0;
}

int RunDiff(const CtlContext& context, int64_t before, int64_t after, const std::string& png) {
  v1::GetGlobalMapRequest request;
  request.set_version(before);
  v1::GlobalMap map_before, map_after;
  QuantizedGrid grid_before, grid_after;
  grpc::Status status = FetchMap(context, request, &map_before, &grid_before);
  if (!status.ok()) return Fail(status, "diff (version " + std::to_string(before) + ")");
  request.set_version(after);
  request.set_resolution(grid_before.geometry.resolution);  // compare cell for cell
  status = FetchMap(context, request, &map_after, &grid_after);
  if (!status.ok()) return Fail(status, "diff (version " + std::to_string(after) + ")");
  const MapDiff diff = DiffMaps(grid_before, grid_after);
  std::string error;
  if (!png.empty() && diff.width > 0 &&
      !WritePng(png, diff.width, diff.height, 3, diff.rgb, &error)) {
    std::cerr << "fleetmapctl: diff failed: " << error << "\n";
    return 1;
  }
  if (context.json) {
    *context.out << "{\"before\": " << before << ", \"after\": " << after
                 << ", \"cells_compared\": " << diff.cells_compared
                 << ", \"changed\": " << diff.changed
                 << ", \"became_occupied\": " << diff.became_occupied
                 << ", \"became_free\": " << diff.became_free
                 << ", \"became_unknown\": " << diff.became_unknown << ", \"image\": \"" << png
                 << "\"}\n";
  } else {
    *context.out << "version " << before << " -> " << after << ": " << diff.changed
                 << " cells changed of " << diff.cells_compared << " (" << diff.became_occupied
                 << " became occupied, " << diff.became_free << " free, " << diff.became_unknown
                 << " unknown)" << (png.empty() ? "" : "; picture in " + png) << "\n";
  }
  return 0;
}

}  // namespace fleetmap
