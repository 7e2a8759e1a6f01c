// match_bias: how far a scan matcher is off at true poses. A map is built from a log's scans
// inserted at their ground-truth poses, and each scan is matched against it from its true pose
// before it is inserted: the heading of the match should be zero. A mean away from zero is a bias
// that SLAM chains up scan after scan (issue 5, session 12). Two matchers:
// - particle: the RBPF's per-particle match (MatchAgainstTiles) and the peak of its scan
//   likelihood, against one particle map of keyframes `--stride` apart;
// - frontend: the scan-matching backend's match (MatchScan, refinement only, as with odometry)
//   against its local map of recent scans (LocalMatchMap), with its insertion filter; every
//   scan is matched, as the frontend does.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "robot_agent/slam/local_match_map.h"
#include "robot_agent/slam/log_runner.h"
#include "robot_agent/slam/particle_filter.h"
#include "robot_agent/slam/particle_scan_matcher.h"
#include "robot_agent/slam/scan_matching_slam.h"
#include "robot_agent/slam/shared_grid_tiles.h"
#include "shared/io/trajectory_file.h"
#include "shared/matching/point_filter.h"
#include "shared/matching/scan_matcher.h"

namespace fleetmap {
namespace {

constexpr double kDegrees = 180.0 / M_PI;

struct Settings {
  std::string log, truth;
  std::string matcher = "particle";
  double stride = 1.0;      // the RBPF's update_translation (particle matcher)
  float max_range = 20.0f;  // ParticleSlamOptions::max_range
  float voxel = 0.1f;       // ParticleSlamOptions::match_voxel
  // Frontend matcher: the scan thinned as the frontend does (ThinBeams at this spacing, 0: every
  // return), or instead to one return per voxel (VoxelFilter, the frontend's thinning until
  // session 14), in beam order or in reverse.
  float beam_spacing = ScanMatchingSlamOptions().match_beam_spacing;
  float frontend_voxel = 0.0f;
  bool reverse_beams = false;
  bool verbose = false;
};

struct Summary {
  int count = 0;
  double sum = 0.0, sum_squares = 0.0;
  void Add(double value) {
    ++count;
    sum += value;
    sum_squares += value * value;
  }
  double Mean() const { return count ? sum / count : 0.0; }
  double Rms() const { return count ? std::sqrt(sum_squares / count) : 0.0; }
};

// The heading offset in [-0.01, 0.01] rad (0.00025 steps) where the likelihood peaks.
double LikelihoodPeakHeading(const std::vector<Eigen::Vector2f>& points, const SharedTileGrid& map,
                             const Rigid2d& pose, const ParticleMatcherOptions& options) {
  double best = -1e300, peak = 0.0;
  for (int i = -40; i <= 40; ++i) {
    const double heading = i * 0.00025;
    const double value = ScanLogLikelihood(points, map, pose * Rigid2d(0.0, 0.0, heading), options);
    if (value > best) {
      best = value;
      peak = heading;
    }
  }
  return peak;
}

// The particle filter's insertion of a keyframe (ParticleFilter::InsertScan), at `pose`.
void InsertAt(const LaserScan& scan, const Rigid2d& pose, float max_range, SharedTileGrid* map) {
  ParticleScan rays;
  SetRays(scan, max_range, &rays);
  std::vector<Eigen::Vector2d> ends;
  ends.reserve(rays.ray_ends.size());
  for (const Eigen::Vector2d& end : rays.ray_ends) ends.push_back(pose * end);
  map->InsertRays(pose * rays.sensor_origin, ends, rays.ray_hits);
}

// The pose of the latest truth sample at or before `timestamp` (advancing `next`).
Rigid2d TruthAt(const Trajectory& truth, double timestamp, size_t* next) {
  while (*next + 1 < truth.size() && truth[*next + 1].timestamp <= timestamp + 1e-6) ++*next;
  return truth[*next].pose;
}

int RunParticle(const Settings& settings, const SlamLog& log, const Trajectory& truth) {
  SharedTileGrid map;
  const ParticleMatcherOptions matcher;
  Summary match_heading, peak_heading;
  size_t t = 0;
  bool first = true;
  Rigid2d last_keyframe;
  for (const LaserScan& scan : log.scans) {
    const Rigid2d pose = TruthAt(truth, scan.timestamp, &t);
    const Rigid2d moved = last_keyframe.inverse() * pose;
    if (!first && moved.translation().norm() < settings.stride && std::abs(moved.rotation()) < 0.5) continue;
    if (!first) {
      LaserScan limited = scan;
      for (float& range : limited.ranges) {
        if (range > settings.max_range) range = LaserScan::kNoReturn;
      }
      const std::vector<Eigen::Vector2f> points = VoxelFilter(ToPointsInRobotFrame(limited), settings.voxel);
      const ParticleMatch match = MatchAgainstTiles(points, map, pose, matcher);
      const double from_match = (pose.inverse() * match.pose).rotation();
      const double from_peak = LikelihoodPeakHeading(points, map, pose, matcher);
      match_heading.Add(from_match);
      peak_heading.Add(from_peak);
      if (settings.verbose) {
        std::printf("%9.2f s  (%7.2f, %7.2f)  match %+7.3f deg  likelihood peak %+7.3f deg\n", scan.timestamp,
                    pose.translation().x(), pose.translation().y(), from_match * kDegrees, from_peak * kDegrees);
      }
    }
    InsertAt(scan, pose, settings.max_range, &map);
    last_keyframe = pose;
    first = false;
  }
  std::printf("%d keyframes %.2f m apart: match heading %+.4f deg mean, %.4f deg RMS; "
              "likelihood peak %+.4f deg mean, %.4f deg RMS\n",
              match_heading.count, settings.stride, match_heading.Mean() * kDegrees,
              match_heading.Rms() * kDegrees, peak_heading.Mean() * kDegrees, peak_heading.Rms() * kDegrees);
  return 0;
}

int RunFrontend(const Settings& settings, const SlamLog& log, const Trajectory& truth) {
  ScanMatchingSlamOptions options;
  options.max_range = settings.max_range;
  LocalMatchMap map(options.local_map);
  ScanMatcherOptions matcher = options.matcher;
  matcher.use_correlative_search = false;
  Summary heading;
  size_t t = 0;
  std::optional<Rigid2d> last_inserted;
  for (const LaserScan& scan : log.scans) {
    const Rigid2d pose = TruthAt(truth, scan.timestamp, &t);
    if (last_inserted) {
      std::vector<Eigen::Vector2f> points;
      if (settings.frontend_voxel > 0.0f) {
        points = ReturnsInsideHorizon(scan, options.max_range, options.match_range_margin);
        if (settings.reverse_beams) std::reverse(points.begin(), points.end());
        points = VoxelFilter(points, settings.frontend_voxel);
        if (settings.reverse_beams) std::reverse(points.begin(), points.end());
      } else {
        points = ReturnsInsideHorizon(ThinBeams(scan, settings.beam_spacing), options.max_range,
                                      options.match_range_margin);
      }
      const std::optional<ScanMatchResult> match = MatchScan(points, map.target(), nullptr, pose, pose, matcher);
      if (match) {
        const double error = (pose.inverse() * match->pose).rotation();
        heading.Add(error);
        if (settings.verbose) {
          std::printf("%9.2f s  (%7.2f, %7.2f)  match %+7.3f deg\n", scan.timestamp, pose.translation().x(),
                      pose.translation().y(), error * kDegrees);
        }
      }
    }
    const Rigid2d moved = last_inserted ? last_inserted->inverse() * pose : Rigid2d();
    if (!last_inserted || moved.translation().norm() >= options.insert_min_translation ||
        std::abs(moved.rotation()) >= options.insert_min_rotation) {
      map.Insert(RangeFilter(ToPointsInRobotFrame(scan), options.max_range), {}, NoReturnEnds(scan, options.max_range),
                 pose);
      last_inserted = pose;
    }
  }
  std::printf("%d scans matched against the frontend's local map: heading %+.4f deg mean, %.4f deg RMS\n",
              heading.count, heading.Mean() * kDegrees, heading.Rms() * kDegrees);
  return 0;
}

int Run(const Settings& settings) {
  SlamLog log;
  Trajectory truth;
  std::string error;
  if (!LoadSlamLog(settings.log, SlamLogOptions(), &log, &error) ||
      !ReadTrajectory(settings.truth, &truth, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  if (truth.empty()) {
    std::fprintf(stderr, "error: %s holds no poses\n", settings.truth.c_str());
    return 1;
  }
  return settings.matcher == "frontend" ? RunFrontend(settings, log, truth) : RunParticle(settings, log, truth);
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) {
  CLI::App app{"Heading error of a scan matcher at true poses: a map of scans at their ground-truth "
               "poses, each scan matched from its true pose before it is inserted. Prints the mean (bias) "
               "and RMS."};
  fleetmap::Settings settings;
  app.add_option("--log", settings.log, "CARMEN log (e.g. fleetmap-sim's robot1.clf)")->required();
  app.add_option("--truth", settings.truth, "Ground-truth trajectory (timestamp x y theta per line)")->required();
  app.add_option("--matcher", settings.matcher,
                 "particle (the RBPF's per-particle match and likelihood) or frontend (the scan-matching "
                 "backend's match against its local map)")
      ->capture_default_str()->check(CLI::IsMember({"particle", "frontend"}));
  app.add_option("--stride", settings.stride, "Keyframe spacing, metres (particle matcher)")->capture_default_str()
      ->check(CLI::Range(0.01, 100.0));
  app.add_option("--max-range", settings.max_range, "Returns farther than this are not used, metres")
      ->capture_default_str()->check(CLI::Range(0.5f, 100.0f));
  app.add_option("--beam-spacing", settings.beam_spacing,
                 "Frontend matcher: thin each scan's near beams to returns this far apart, as the frontend does (0: every return)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f));
  app.add_option("--frontend-voxel", settings.frontend_voxel,
                 "Frontend matcher: thin each scan to one return per voxel of this size instead (0: off)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f));
  app.add_flag("--reverse-beams", settings.reverse_beams, "Frontend matcher: voxels filled in reverse beam order");
  app.add_flag("--verbose", settings.verbose, "One line per matched scan");
  CLI11_PARSE(app, argc, argv);
  return fleetmap::Run(settings);
}
