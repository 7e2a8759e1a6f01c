// Detection benchmark: speed, precision/recall, range/bearing accuracy, distractor rejection and
// covariance honesty on synthetic frames (rooms, up to three other robots, same-coloured posters,
// random lighting) rendered by robot_agent/detection/synthetic.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Dense>

#include "robot_agent/detection/image_io.h"
#include "robot_agent/detection/robot_detector.h"
#include "robot_agent/detection/synthetic/synthetic_dataset.h"

namespace fleetmap {
namespace {

struct Tally {
  long eligible = 0, eligible_detected = 0;
  long detections = 0, true_detections = 0, false_detections = 0;
  long distractor_candidates = 0, distractor_detections = 0;
  long inside_95 = 0, inside_2sigma = 0;
  double range_sq = 0.0, bearing_sq = 0.0;
  long error_count = 0;
  std::vector<double> image_seconds, full_seconds;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

const synthetic::Sighting* Match(const std::vector<synthetic::Sighting>& truth,
                                 const std::string& id, const Eigen::Vector2d& position,
                                 double gate) {
  for (const synthetic::Sighting& s : truth) {
    if (s.robot_id == id && (s.position_in_observer - position).norm() < gate) return &s;
  }
  return nullptr;
}

int Run(int argc, char** argv) {
  CLI::App app{"Benchmark of robot detection (image stage, laser fusion) on synthetic frames"};
  int frames = 1000, train_frames = 40, repeats = 3;
  unsigned seed = 1;
  double max_range = 8.0;
  std::string dump_dir;
  bool verbose = false;
  app.add_option("--frames", frames, "test frames")->check(CLI::Range(1, 1000000));
  app.add_option("--train-frames", train_frames, "calibration frames")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "first test frame seed");
  app.add_option("--repeats", repeats, "timing repetitions per frame")->check(CLI::Range(1, 100));
  app.add_option("--max-range", max_range, "eligible markers are within this range, metres");
  app.add_option("--dump-dir", dump_dir, "write the first 20 test frames as PNG here");
  app.add_flag("--verbose", verbose, "print every miss and false detection");
  CLI11_PARSE(app, argc, argv);

  CameraModel camera;
  camera.camera_in_robot = Rigid2d(0.05, 0.0, 0.0);
  MarkerGeometry geometry;
  synthetic::LaserOptions laser;
  laser.sensor_in_robot = Rigid2d(0.12, 0.0, 0.0);
  synthetic::SceneOptions scene;

  std::fprintf(stderr, "calibrating on %d frames...\n", train_frames);
  const ColourModel colours =
      synthetic::LearnColourModel(camera, geometry, scene, train_frames, 1000000u + seed);
  std::string error;
  const auto detector = RobotDetector::Create(camera, geometry, colours, {}, &error);
  if (!detector) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }

  Tally tally;
  using Clock = std::chrono::steady_clock;
  for (int f = 0; f < frames; ++f) {
    if (f % 100 == 0) std::fprintf(stderr, "frame %d/%d\n", f, frames);
    const synthetic::Frame frame = synthetic::MakeRandomFrame(camera, geometry, laser, scene, seed + f);
    if (!dump_dir.empty() && f < 20) {
      WriteBgrImage(dump_dir + "/frame" + std::to_string(f) + ".png", frame.image, &error);
    }
    std::vector<MarkerCandidate> candidates;
    FrameDetections result;
    double best_image = 1e9, best_full = 1e9;
    for (int r = 0; r < repeats; ++r) {
      auto t0 = Clock::now();
      detector->marker_detector().Detect(frame.image.view(), &candidates, &error);
      auto t1 = Clock::now();
      detector->Detect(frame.image.view(), frame.scan, frame.observer_id, &result, &error);
      auto t2 = Clock::now();
      best_image = std::min(best_image, std::chrono::duration<double>(t1 - t0).count());
      best_full = std::min(best_full, std::chrono::duration<double>(t2 - t1).count());
    }
    tally.image_seconds.push_back(best_image);
    tally.full_seconds.push_back(best_full);

    for (const MarkerCandidate& c : result.candidates) {
      bool near_robot = false;
      for (const synthetic::Sighting& s : frame.truth) {
        if (s.robot_id == c.robot_id && (s.position_in_observer - c.position_in_robot).norm() <
                                            0.5 + 0.35 * s.position_in_observer.norm()) {
          near_robot = true;
        }
      }
      if (!near_robot) ++tally.distractor_candidates;
    }
    for (const RobotDetection& d : result.detections) {
      ++tally.detections;
      const synthetic::Sighting* s = Match(frame.truth, d.observed_id, d.position_in_observer, 0.5);
      if (s == nullptr) {
        ++tally.false_detections;
        if (verbose) {
          std::printf("frame %d: false detection of %s at (%.2f, %.2f), %d returns, rms %.3f\n",
                      f, d.observed_id.c_str(), d.position_in_observer.x(),
                      d.position_in_observer.y(), d.laser_returns, d.fit_rms);
        }
        if (!Match(frame.truth, d.observed_id, d.position_in_observer, 1e9)) continue;
        ++tally.distractor_detections;
        continue;
      }
      ++tally.true_detections;
    }
    for (const synthetic::Sighting& s : frame.truth) {
      if (!s.fully_in_view || s.occluded || s.position_in_observer.norm() > max_range) continue;
      ++tally.eligible;
      const long before = tally.eligible_detected;
      for (const RobotDetection& d : result.detections) {
        if (d.observed_id != s.robot_id || (d.position_in_observer - s.position_in_observer).norm() > 0.5) {
          continue;
        }
        ++tally.eligible_detected;
        const Eigen::Vector2d e = d.position_in_observer - s.position_in_observer;
        const double range_error = d.range() - s.position_in_observer.norm();
        const double bearing_error = NormalizeAngle(
            d.bearing() - std::atan2(s.position_in_observer.y(), s.position_in_observer.x()));
        tally.range_sq += range_error * range_error;
        tally.bearing_sq += bearing_error * bearing_error;
        ++tally.error_count;
        const double d2 = e.dot(d.covariance.inverse() * e);
        if (d2 <= 5.991) ++tally.inside_95;
        if (d2 <= 4.0) ++tally.inside_2sigma;
      }
      if (verbose && tally.eligible_detected == before) {
        std::printf("frame %d: missed %s at range %.2f camera bearing %.1f deg; candidates:", f,
                    s.robot_id.c_str(), s.position_in_observer.norm(),
                    s.camera_bearing * 180.0 / M_PI);
        for (size_t c = 0; c < result.candidates.size(); ++c) {
          std::printf(" [%s %.2fm %.1fdeg %s]", result.candidates[c].robot_id.c_str(),
                      result.candidates[c].range_from_size,
                      result.candidates[c].bearing_in_camera * 180.0 / M_PI,
                      FusionStatusName(result.statuses[c]));
        }
        std::printf("\n");
      }
    }
  }

  const double n = std::max<long>(1, tally.error_count);
  double image_total = 0.0, full_total = 0.0;
  for (double s : tally.image_seconds) image_total += s;
  for (double s : tally.full_seconds) full_total += s;
  std::printf("| figure | target | measured |\n|---|---|---|\n");
  std::printf("| image stage, 640x480, one core | >= 500 fps | %.0f fps (mean %.3f ms, median %.3f ms) |\n",
              frames / image_total, 1e3 * image_total / frames, 1e3 * Median(tally.image_seconds));
  std::printf("| image + laser fusion | >= 200 fps | %.0f fps (mean %.3f ms, median %.3f ms) |\n",
              frames / full_total, 1e3 * full_total / frames, 1e3 * Median(tally.full_seconds));
  std::printf("| precision (all confirmed detections) | >= 0.99 | %.4f (%ld / %ld) |\n",
              tally.true_detections / std::max(1.0, double(tally.detections)), tally.true_detections,
              tally.detections);
  std::printf("| recall (fully in view, not occluded, <= %.0f m) | >= 0.95 | %.4f (%ld / %ld) |\n",
              max_range, tally.eligible_detected / std::max(1.0, double(tally.eligible)),
              tally.eligible_detected, tally.eligible);
  std::printf("| range error RMS | <= 3 cm | %.2f cm |\n", 100.0 * std::sqrt(tally.range_sq / n));
  std::printf("| bearing error RMS | <= 0.5 deg | %.3f deg |\n",
              std::sqrt(tally.bearing_sq / n) * 180.0 / M_PI);
  std::printf("| false detections from same-coloured posters, after laser | 0 | %ld (%ld poster candidates passed the image stage) |\n",
              tally.distractor_detections, tally.distractor_candidates);
  std::printf("| errors inside the 95%% ellipse (d2 <= 5.99) | ~95%% | %.1f%% |\n",
              100.0 * tally.inside_95 / n);
  std::printf("| errors inside the 2-sigma ellipse (d2 <= 4) | ~86.5%% (chi2, 2 dof) | %.1f%% |\n",
              100.0 * tally.inside_2sigma / n);
  std::printf("\n%d frames, seed %u, %d calibration frames; false detections of any kind: %ld\n",
              frames, seed, train_frames, tally.false_detections);
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }
