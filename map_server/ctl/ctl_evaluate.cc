#include "map_server/ctl/ctl_evaluate.h"

#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>

#include "map_server/ctl/localization_error.h"
#include "shared/eval/wall_score.h"
#include "shared/io/map_file.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {

bool ReadStartPoses(const std::string& path, std::map<std::string, Rigid2d>* starts,
                    std::string* error) {
  try {
    const YAML::Node root = YAML::LoadFile(path);
    const YAML::Node robots = root["robots"];
    if (!robots || !robots.IsSequence()) {
      *error = path + ": expected a list 'robots'";
      return false;
    }
    for (const YAML::Node& robot : robots) {
      if (!robot["name"] || !robot["start"]) {
        *error = path + ": every robot needs 'name' and 'start'";
        return false;
      }
      const YAML::Node s = robot["start"];
      const Rigid2d pose(s["x"].as<double>(), s["y"].as<double>(), s["theta"].as<double>());
      if (!pose.IsFinite()) {
        *error = path + ": non-finite start pose for " + robot["name"].as<std::string>();
        return false;
      }
      (*starts)[robot["name"].as<std::string>()] = pose;
    }
  } catch (const YAML::Exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  if (starts->empty()) {
    *error = path + ": no robots listed";
    return false;
  }
  return true;
}

MergeEvaluation EvaluatePlacements(const std::map<std::string, Rigid2d>& placements,
                                   const std::map<std::string, Rigid2d>& truth) {
  MergeEvaluation result;
  std::optional<std::string> reference;
  for (const auto& [name, start] : truth) {
    if (placements.count(name) == 0) {
      result.unplaced.push_back(name);
    } else if (!reference) {
      reference = name;
    }
  }
  if (!reference) return result;
  const Rigid2d& ref_global = placements.at(*reference);
  const Rigid2d& ref_world = truth.at(*reference);
  for (const auto& [name, start] : truth) {
    if (name == *reference || placements.count(name) == 0) continue;
    // The robot's local frame expressed in the reference robot's local frame, both ways.
    const Rigid2d estimated = ref_global.inverse() * placements.at(name);
    const Rigid2d expected = ref_world.inverse() * start;
    result.pairs.push_back({*reference, name,
                            (estimated.translation() - expected.translation()).norm(),
                            std::abs(NormalizeAngle(estimated.rotation() - expected.rotation()))});
  }
  return result;
}

int RunEvaluate(const CtlContext& context, const EvaluateOptions& options) {
  std::map<std::string, Rigid2d> truth;
  std::string error;
  if (!ReadStartPoses(options.ground_truth, &truth, &error)) {
    std::cerr << "fleetmapctl: " << error << "\n";
    return 1;
  }
  // Localizing robots: ID=TRUE_TRAJECTORY, read before asking the server.
  std::vector<std::pair<std::string, Trajectory>> localized;
  for (const std::string& item : options.localized) {
    const size_t equals = item.find('=');
    Trajectory true_poses;
    if (equals == std::string::npos || equals == 0) {
      std::cerr << "fleetmapctl: --localized: expected ROBOT=TRUE_TRAJECTORY, got '" << item
                << "'\n";
      return 1;
    }
    if (!ReadTrajectory(item.substr(equals + 1), &true_poses, &error)) {
      std::cerr << "fleetmapctl: --localized: " << error << "\n";
      return 1;
    }
    localized.emplace_back(item.substr(0, equals), std::move(true_poses));
  }
  v1::GetRobotsRequest request;
  request.set_include_trajectories(!localized.empty());
  v1::GetRobotsResponse response;
  grpc::ClientContext rpc;
  rpc.set_deadline(std::chrono::system_clock::now() +
                   std::chrono::milliseconds(static_cast<int64_t>(context.timeout_seconds * 1e3)));
  const grpc::Status status = context.stub->GetRobots(&rpc, request, &response);
  if (!status.ok()) {
    std::cerr << "fleetmapctl: evaluate failed: " << status.error_message() << "\n";
    return 1;
  }
  // Each robot's frame where its first submap puts it, as the ground truth gives the robots'
  // starts (and as the simulator benchmarks score). The frame its newest submap implies
  // (local_in_global) also carries the robot's local SLAM drift since its start; it is the
  // fallback for a server that does not report the start.
  std::map<std::string, Rigid2d> placements;
  int from_newest_submap = 0;
  for (const v1::RobotInfo& r : response.robots()) {
    if (!r.placement().placed()) continue;
    const bool has_start = r.placement().has_start_in_global();
    from_newest_submap += !has_start;
    const v1::Pose2d& p =
        has_start ? r.placement().start_in_global() : r.placement().local_in_global();
    placements[r.robot_id()] = Rigid2d(p.x(), p.y(), p.theta());
  }
  MergeEvaluation evaluation = EvaluatePlacements(placements, truth);

  if (!options.map.empty() && !options.world.empty() && !evaluation.pairs.empty()) {
    OccupancyGrid global_map, world;
    if (!ReadMap(options.map, &global_map, &error) || !ReadMap(options.world, &world, &error)) {
      std::cerr << "fleetmapctl: " << error << "\n";
      return 1;
    }
    const std::string& reference = evaluation.pairs.front().reference;
    const Rigid2d world_from_global = truth.at(reference) * placements.at(reference).inverse();
    // The rule the simulator benchmarks and the end-to-end tests score with (WallMask).
    const WallMask walls = WallMask::FromTrueMap(world, options.tolerance_cells);
    const WallScore score = ScoreOnWalls(global_map, world_from_global, walls);
    evaluation.occupied_cells = static_cast<long>(score.occupied);
    evaluation.map_accuracy = score.fraction();
    evaluation.map_accuracy_best_fit =
        ScoreOnWallsBestFit(global_map, world_from_global, walls).fraction();
  }

  // The world frame through the reference robot (the first placed robot of the ground truth).
  std::optional<Rigid2d> world_from_global;
  for (const auto& [name, start] : truth) {
    if (placements.count(name)) {
      world_from_global = start * placements.at(name).inverse();
      break;
    }
  }
  std::vector<std::pair<std::string, LocalizationError>> localization;
  for (const auto& [id, true_poses] : localized) {
    const v1::RobotInfo* robot = nullptr;
    for (const v1::RobotInfo& r : response.robots()) {
      if (r.robot_id() == id) robot = &r;
    }
    if (!robot) {
      std::cerr << "fleetmapctl: --localized: the server has no robot '" << id << "'\n";
      return 1;
    }
    if (!world_from_global) {
      std::cerr << "fleetmapctl: --localized: no robot of the ground truth is placed, so the "
                   "global frame cannot be related to the world\n";
      return 1;
    }
    Trajectory in_world;
    for (const v1::StampedPose& p : robot->trajectory_in_global()) {
      in_world.push_back({p.timestamp(), *world_from_global * Rigid2d(p.pose().x(), p.pose().y(),
                                                                      p.pose().theta())});
    }
    localization.emplace_back(id, ScoreTrajectory(in_world, true_poses));
  }

  double worst_t = 0.0, worst_r = 0.0;
  for (const PairError& e : evaluation.pairs) {
    worst_t = std::max(worst_t, e.translation_error);
    worst_r = std::max(worst_r, e.rotation_error);
  }
  std::ostream& out = *context.out;
  out << std::fixed;
  if (context.json) {
    out << "{\n  \"pairs\": [";
    for (size_t i = 0; i < evaluation.pairs.size(); ++i) {
      const PairError& e = evaluation.pairs[i];
      out << (i ? ",\n" : "\n") << "    {\"reference\": \"" << e.reference << "\", \"robot\": \""
          << e.robot << "\", \"translation_error_m\": " << std::setprecision(4)
          << e.translation_error << ", \"rotation_error_deg\": " << e.rotation_error * 180 / M_PI
          << "}";
    }
    out << "\n  ],\n  \"unplaced\": [";
    for (size_t i = 0; i < evaluation.unplaced.size(); ++i) {
      out << (i ? ", " : "") << "\"" << evaluation.unplaced[i] << "\"";
    }
    out << "],\n  \"worst_translation_error_m\": " << worst_t
        << ",\n  \"worst_rotation_error_deg\": " << worst_r * 180 / M_PI
        << ",\n  \"placed_by_newest_submap\": " << from_newest_submap;
    if (evaluation.map_accuracy) {
      out << ",\n  \"map_accuracy\": " << *evaluation.map_accuracy
          << ",\n  \"map_accuracy_best_fit\": " << *evaluation.map_accuracy_best_fit
          << ",\n  \"occupied_cells\": " << evaluation.occupied_cells;
    }
    if (!localization.empty()) {
      out << ",\n  \"localization\": [";
      for (size_t i = 0; i < localization.size(); ++i) {
        const LocalizationError& e = localization[i].second;
        out << (i ? ",\n" : "\n") << "    {\"robot\": \"" << localization[i].first
            << "\", \"poses\": " << e.matched << std::setprecision(4)
            << ", \"mean_position_error_m\": " << e.mean_position
            << ", \"max_position_error_m\": " << e.max_position
            << ", \"mean_heading_error_deg\": " << e.mean_heading * 180 / M_PI
            << ", \"max_heading_error_deg\": " << e.max_heading * 180 / M_PI
            << ", \"final_position_error_m\": " << e.final_position << "}";
      }
      out << "\n  ]";
    }
    out << "\n}\n";
  } else {
    out << "merge against ground truth (" << truth.size() << " robots, " << placements.size()
        << " placed by the server; each robot's frame where its first submap places it";
    if (from_newest_submap > 0) {
      out << ", except " << from_newest_submap << " for which the server reported only its newest";
    }
    out << ")\n";
    for (const PairError& e : evaluation.pairs) {
      out << "  " << e.robot << " relative to " << e.reference << ": " << std::setprecision(3)
          << e.translation_error << " m, " << std::setprecision(2) << e.rotation_error * 180 / M_PI
          << " deg\n";
    }
    for (const std::string& name : evaluation.unplaced) out << "  " << name << ": NOT PLACED\n";
    if (evaluation.map_accuracy) {
      out << "  map: " << std::setprecision(1) << *evaluation.map_accuracy * 100.0 << " % of "
          << evaluation.occupied_cells << " occupied cells within " << options.tolerance_cells
          << " cell of a true wall (" << *evaluation.map_accuracy_best_fit * 100.0
          << " % at the best rigid placement within 0.18 m / 0.35 deg)\n";
    }
    for (const auto& [id, e] : localization) {
      out << "  " << id << " (localizing in the global map): " << e.matched
          << " poses scored; mean " << std::setprecision(3) << e.mean_position << " m, "
          << std::setprecision(2) << e.mean_heading * 180 / M_PI << " deg; worst "
          << std::setprecision(3) << e.max_position << " m, " << std::setprecision(2)
          << e.max_heading * 180 / M_PI << " deg; at the end " << std::setprecision(3)
          << e.final_position << " m\n";
    }
  }
  return evaluation.unplaced.empty() ? 0 : 2;
}

}  // namespace fleetmap
