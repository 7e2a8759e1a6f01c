// fleetmap-detect-calibrate: learns the marker colour histograms from labelled frames and saves
// the colour model (YAML) the detector loads.
//
// Labels file: one marker per line, "image_path robot_id x y width height" (box in pixels,
// image paths relative to the labels file); '#' starts a comment. Frames without markers may be
// listed as "image_path -" so that they teach the background.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "robot_agent/detection/calibration.h"
#include "robot_agent/detection/colour_model_io.h"
#include "robot_agent/detection/image_io.h"
#include "robot_agent/detection/synthetic/synthetic_dataset.h"
#include "robot_agent/detection/tools/sim_dataset.h"

namespace fleetmap {
namespace {

bool ReadLabels(const std::string& path,
                std::map<std::string, std::vector<LabelledMarker>>* frames, std::string* error) {
  std::ifstream file(path);
  if (!file) {
    *error = path + ": cannot open labels file";
    return false;
  }
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::string image, robot_id;
    if (!(in >> image)) continue;
    const std::string image_path = (base / image).string();
    auto& markers = (*frames)[image_path];
    if (!(in >> robot_id) || robot_id == "-") continue;
    LabelledMarker marker{robot_id, {}};
    if (!(in >> marker.box.x >> marker.box.y >> marker.box.width >> marker.box.height)) {
      *error = path + ":" + std::to_string(number) +
               ": expected 'image_path robot_id x y width height'";
      return false;
    }
    markers.push_back(marker);
  }
  return true;
}

// Labels of every frame of a simulator run, from its visibility list: visible markers are
// learnt, markers in front of the camera but hidden are only kept out of the background.
bool SimLabels(const std::string& dir, int max_frames,
               std::map<std::string, std::vector<LabelledMarker>>* frames, std::string* error) {
  SimDataset data;
  if (!ReadSimDataset(dir, &data, error)) return false;
  std::vector<std::pair<std::string, std::vector<LabelledMarker>>> with_markers, without;
  for (const SimRobot& robot : data.robots) {
    for (const SimCameraFrame& frame : robot.frames) {
      std::vector<LabelledMarker> labels;
      const auto first = std::lower_bound(
          data.visibility.begin(), data.visibility.end(), frame.timestamp - 1e-4,
          [](const SimVisibility& v, double t) { return v.timestamp < t; });
      for (auto it = first; it != data.visibility.end() && it->timestamp <= frame.timestamp + 1e-4;
           ++it) {
        if (it->observer != robot.name) continue;
        const Eigen::Vector2d in_camera = frame.camera.camera_in_robot.inverse() * it->relative;
        const ImageBox box =
            ProjectMarker(frame.camera, data.geometry, in_camera.norm(),
                          std::atan2(in_camera.y(), in_camera.x()));
        if (box.width <= 0 || box.height <= 0) continue;
        labels.push_back({it->observed, box, !it->visible});
      }
      const bool any = std::any_of(labels.begin(), labels.end(),
                                   [](const LabelledMarker& m) { return !m.exclude_only; });
      (any ? with_markers : without).push_back({frame.image_path, labels});
    }
  }
  // Mostly frames with markers, a quarter without, spread evenly over the run.
  auto take = [&](const auto& list, size_t count) {
    for (size_t i = 0; i < count && !list.empty(); ++i) {
      const auto& entry = list[i * list.size() / count];
      (*frames)[entry.first] = entry.second;
    }
  };
  const size_t budget = static_cast<size_t>(max_frames);
  take(with_markers, std::min(with_markers.size(), budget * 3 / 4));
  take(without, std::min(without.size(), budget - std::min(with_markers.size(), budget * 3 / 4)));
  std::fprintf(stderr, "%zu frames with visible markers, %zu without; using %zu\n",
               with_markers.size(), without.size(), frames->size());
  return true;
}

int Run(int argc, char** argv) {
  CLI::App app{"Learn marker colour histograms from labelled frames and save the colour model"};
  std::string labels, out;
  int synthetic_frames = 0;
  unsigned seed = 1;
  app.add_option("--labels", labels, "labels file: 'image_path robot_id x y width height' lines");
  app.add_option("--synthetic", synthetic_frames,
                 "instead of --labels, learn from this many rendered synthetic frames")
      ->check(CLI::Range(1, 100000));
  std::string sim_dir;
  int max_frames = 400;
  app.add_option("--sim-dir", sim_dir,
                 "instead of --labels, label the frames of a fleetmap-sim output folder");
  app.add_option("--max-frames", max_frames, "frames used with --sim-dir")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--seed", seed, "first seed of the synthetic frames");
  app.add_option("--out", out, "colour model to write (YAML)")->required();
  CLI11_PARSE(app, argc, argv);
  if (int(!labels.empty()) + int(synthetic_frames > 0) + int(!sim_dir.empty()) != 1) {
    std::fprintf(stderr, "error: give exactly one of --labels, --sim-dir or --synthetic\n");
    return 2;
  }

  std::string error;
  ColourModel model;
  if (synthetic_frames > 0) {
    std::fprintf(stderr, "learning from %d synthetic frames...\n", synthetic_frames);
    model = synthetic::LearnColourModel(CameraModel(), MarkerGeometry(), synthetic::SceneOptions(),
                                        synthetic_frames, seed);
  } else {
    std::map<std::string, std::vector<LabelledMarker>> frames;
    if (!(sim_dir.empty() ? ReadLabels(labels, &frames, &error)
                          : SimLabels(sim_dir, max_frames, &frames, &error))) {
      std::fprintf(stderr, "error: %s\n", error.c_str());
      return 1;
    }
    ColourCalibrator calibrator;
    int done = 0;
    for (const auto& [path, markers] : frames) {
      BgrImage image;
      if (!ReadBgrImage(path, &image, &error) ||
          !calibrator.AddFrame(image.view(), markers, &error)) {
        std::fprintf(stderr, "error: %s: %s\n", path.c_str(), error.c_str());
        return 1;
      }
      if (++done % 50 == 0) std::fprintf(stderr, "%d/%zu frames\n", done, frames.size());
    }
    model = calibrator.Build();
  }
  if (model.markers.empty()) {
    std::fprintf(stderr, "error: no marker pixels were labelled\n");
    return 1;
  }
  if (!model.IsValid(&error) || !WriteColourModel(out, model, &error)) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return 1;
  }
  for (const MarkerColour& marker : model.markers) {
    std::fprintf(stderr, "%s: %.0f marker pixels\n", marker.robot_id.c_str(),
                 marker.histogram.total());
  }
  std::fprintf(stderr, "wrote %s (%zu markers)\n", out.c_str(), model.markers.size());
  return 0;
}

}  // namespace
}  // namespace fleetmap

int main(int argc, char** argv) { return fleetmap::Run(argc, argv); }
