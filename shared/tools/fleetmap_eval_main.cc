// fleetmap-eval: accuracy of a trajectory.
//
//   fleetmap-eval relations --trajectory T.txt --relations R.relations [--json]
//   fleetmap-eval ate --trajectory T.txt --ground-truth G.txt [--align] [--json]

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "shared/eval/absolute_trajectory_error.h"
#include "shared/eval/relations_file.h"
#include "shared/eval/relations_metric.h"
#include "shared/io/trajectory_file.h"

namespace fleetmap {
namespace {

int Fail(const std::string& message) {
  std::fprintf(stderr, "fleetmap-eval: error: %s\n", message.c_str());
  return 1;
}

std::string Json(const char* name, const MeanStd& value) {
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "\"%s\": {\"mean\": %.9g, \"std\": %.9g, \"max\": %.9g}",
                name, value.mean, value.std, value.max);
  return buffer;
}

int RunRelations(const std::string& trajectory_path, const std::string& relations_path,
                 const RelationsOptions& options, bool json) {
  Trajectory trajectory;
  std::vector<Relation> relations;
  std::string error;
  if (!ReadTrajectory(trajectory_path, &trajectory, &error)) return Fail(error);
  if (!ReadRelations(relations_path, &relations, &error)) return Fail(error);
  const RelationsResult r = EvaluateRelations(trajectory, relations, options);
  if (json) {
    std::printf("{\"relations\": %zu, \"used\": %d, \"skipped\": %d, %s, %s, %s, %s}\n",
                relations.size(), r.used, r.skipped, Json("translation_m", r.translation).c_str(),
                Json("squared_translation_m2", r.squared_translation).c_str(),
                Json("rotation_deg", r.rotation_deg).c_str(),
                Json("squared_rotation_deg2", r.squared_rotation_deg).c_str());
  } else {
    std::printf("relations: %d used, %d skipped (of %zu)\n", r.used, r.skipped, relations.size());
    std::printf("translational error  [m]     %10.6f +- %10.6f  (max %.6f)\n", r.translation.mean,
                r.translation.std, r.translation.max);
    std::printf("squared translational [m^2]  %10.6f +- %10.6f\n", r.squared_translation.mean,
                r.squared_translation.std);
    std::printf("rotational error     [deg]   %10.6f +- %10.6f  (max %.6f)\n", r.rotation_deg.mean,
                r.rotation_deg.std, r.rotation_deg.max);
    std::printf("squared rotational  [deg^2]  %10.6f +- %10.6f\n", r.squared_rotation_deg.mean,
                r.squared_rotation_deg.std);
  }
  if (r.used == 0) return Fail("no relation matched the trajectory's timestamps");
  return 0;
}

int RunAte(const std::string& trajectory_path, const std::string& ground_truth_path,
           const AteOptions& options, bool json) {
  Trajectory estimate;
  Trajectory ground_truth;
  std::string error;
  if (!ReadTrajectory(trajectory_path, &estimate, &error)) return Fail(error);
  if (!ReadTrajectory(ground_truth_path, &ground_truth, &error)) return Fail(error);
  const std::optional<AteResult> r = EvaluateAte(estimate, ground_truth, options);
  if (!r) {
    return Fail("no poses could be paired within " + std::to_string(options.max_time_difference) +
                " s" + (options.align ? " (or too few / degenerate for --align)" : ""));
  }
  const Rigid2d& a = r->ground_truth_from_estimate;
  if (json) {
    std::printf(
        "{\"matched\": %d, \"unmatched\": %d, \"rmse_translation_m\": %.9g, "
        "\"rmse_rotation_deg\": %.9g, %s, \"alignment\": [%.9g, %.9g, %.9g]}\n",
        r->matched, r->unmatched, r->rmse_translation, r->rmse_rotation_deg,
        Json("translation_m", r->translation).c_str(), a.x(), a.y(), a.rotation());
  } else {
    std::printf("poses: %d matched, %d unmatched\n", r->matched, r->unmatched);
    std::printf("ATE translation RMSE [m]   %.6f  (mean %.6f, max %.6f)\n", r->rmse_translation,
                r->translation.mean, r->translation.max);
    std::printf("ATE rotation RMSE  [deg]   %.6f\n", r->rmse_rotation_deg);
    if (options.align) {
      std::printf("alignment (ground truth from estimate): x %.6f y %.6f theta %.6f\n", a.x(),
                  a.y(), a.rotation());
    }
  }
  return 0;
}

int Run(int argc, char** argv) {
  CLI::App app{"fleetmap-eval: accuracy of a trajectory file (timestamp x y theta per line)."};
  app.require_subcommand(1);
  std::string trajectory;
  std::string relations;
  std::string ground_truth;
  bool json = false;
  RelationsOptions relations_options;
  AteOptions ate_options;

  CLI::App* rel =
      app.add_subcommand("relations",
                         "Kümmerle et al. 2009 relations metric: error = (pose(t1)^-1 pose(t2)) "
                         "expected^-1 for every relation whose timestamps are in the trajectory");
  rel->add_option("-t,--trajectory", trajectory, "Trajectory file")
      ->required()
      ->check(CLI::ExistingFile);
  rel->add_option("-r,--relations", relations, "Relations file (t1 t2 x y z roll pitch yaw)")
      ->required()
      ->check(CLI::ExistingFile);
  rel->add_option("--tolerance", relations_options.timestamp_tolerance,
                  "Timestamp match tolerance (s)")
      ->capture_default_str();
  rel->add_flag("--json", json, "Print one JSON object");

  CLI::App* ate = app.add_subcommand("ate",
                                     "Absolute trajectory error (RMSE) against a "
                                     "ground-truth trajectory");
  ate->add_option("-t,--trajectory", trajectory, "Estimated trajectory file")
      ->required()
      ->check(CLI::ExistingFile);
  ate->add_option("-g,--ground-truth", ground_truth, "Ground-truth trajectory file")
      ->required()
      ->check(CLI::ExistingFile);
  ate->add_flag("--align", ate_options.align,
                "Rigidly align the estimate to the ground truth first (2D Horn/Umeyama)");
  ate->add_option("--max-time-difference", ate_options.max_time_difference,
                  "Pair poses at most this far apart in time (s)")
      ->capture_default_str();
  ate->add_flag("--json", json, "Print one JSON object");

  CLI11_PARSE(app, argc, argv);
  if (rel->parsed()) return RunRelations(trajectory, relations, relations_options, json);
  return RunAte(trajectory, ground_truth, ate_options, json);
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }
