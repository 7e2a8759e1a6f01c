#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_H_

#include <cstdint>
#include <string>
#include <vector>

#include "robot_agent/detection/colour.h"

namespace fleetmap {

// One robot's marker colour.
struct MarkerColour {
  std::string robot_id;
  ColourHistogram histogram;
};

// What the calibration learns: a histogram per marker and one for everything else. A pixel is
// a marker pixel when its colour is much likelier under a marker's histogram than under the
// background's (the likelihood ratio is the histogram back-projection of the paper, normalised
// by the background so that colours common in the world do not fire).
struct ColourModel {
  std::vector<MarkerColour> markers;
  ColourHistogram background;
  double min_value = 0.08;              // darker pixels carry no reliable hue
  double min_likelihood_ratio = 4.0;    // marker vs background
  double min_marker_probability = 5e-4; // of the marker's own (smoothed) histogram bin
  double background_floor = 0.02;       // share of background mass spread over all bins

  bool IsValid(std::string* error) const;
};

// The colour model compiled into a lookup table over 6-bit-per-channel BGR, so classifying a
// pixel is one memory read (the image stage's speed rests on this).
class ColourLut {
 public:
  static constexpr int kBits = 6;
  static constexpr int kShift = 8 - kBits;

  explicit ColourLut(const ColourModel& model);

  // 0 for background, otherwise 1 + the index of the marker in the model.
  uint8_t Label(uint8_t b, uint8_t g, uint8_t r) const {
    return labels_[(static_cast<unsigned>(b >> kShift) << (2 * kBits)) |
                   (static_cast<unsigned>(g >> kShift) << kBits) | (r >> kShift)];
  }
  int num_markers() const { return num_markers_; }

 private:
  std::vector<uint8_t> labels_;
  int num_markers_ = 0;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_H_
