#include "robot_agent/detection/colour_model.h"

#include <set>

namespace fleetmap {

bool ColourModel::IsValid(std::string* error) const {
  if (markers.size() > 250) {
    *error = "colour model has more than 250 markers";
    return false;
  }
  std::set<std::string> ids;
  for (const MarkerColour& marker : markers) {
    if (marker.robot_id.empty()) {
      *error = "colour model has a marker without a robot id";
      return false;
    }
    if (!ids.insert(marker.robot_id).second) {
      *error = "colour model lists robot '" + marker.robot_id + "' twice";
      return false;
    }
    if (!(marker.histogram.total() > 0.0)) {
      *error = "marker of robot '" + marker.robot_id + "' has an empty histogram";
      return false;
    }
  }
  if (!(min_likelihood_ratio > 0.0) || !(background_floor > 0.0) || !(background_floor < 1.0)) {
    *error = "colour model thresholds out of range";
    return false;
  }
  return true;
}

ColourLut::ColourLut(const ColourModel& model)
    : labels_(1u << (3 * kBits), 0), num_markers_(static_cast<int>(model.markers.size())) {
  std::vector<std::vector<double>> marker_probabilities;
  for (const MarkerColour& marker : model.markers) {
    marker_probabilities.push_back(marker.histogram.SmoothedProbabilities(0.0));
  }
  const std::vector<double> background =
      model.background.SmoothedProbabilities(model.background_floor);
  constexpr int kLevels = 1 << kBits;
  constexpr int kHalfStep = 1 << (kShift - 1);
  for (int b = 0; b < kLevels; ++b) {
    for (int g = 0; g < kLevels; ++g) {
      for (int r = 0; r < kLevels; ++r) {
        // Classify the centre of the quantisation cell.
        const Hsv hsv = BgrToHsv(static_cast<uint8_t>((b << kShift) + kHalfStep),
                                 static_cast<uint8_t>((g << kShift) + kHalfStep),
                                 static_cast<uint8_t>((r << kShift) + kHalfStep));
        if (hsv.value < model.min_value) continue;
        const int bin = ColourHistogram::BinOf(hsv.hue, hsv.saturation);
        int best = -1;
        double best_probability = 0.0;
        for (int k = 0; k < num_markers_; ++k) {
          if (marker_probabilities[k][bin] > best_probability) {
            best_probability = marker_probabilities[k][bin];
            best = k;
          }
        }
        if (best < 0 || best_probability < model.min_marker_probability) continue;
        if (best_probability < model.min_likelihood_ratio * background[bin]) continue;
        labels_[(b << (2 * kBits)) | (g << kBits) | r] = static_cast<uint8_t>(best + 1);
      }
    }
  }
}

}  // namespace fleetmap
