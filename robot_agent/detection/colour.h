#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_H_

#include <cstdint>
#include <vector>

namespace fleetmap {

struct Hsv {
  double hue = 0.0;         // degrees in [0, 360)
  double saturation = 0.0;  // [0, 1]
  double value = 0.0;       // [0, 1]
};

Hsv BgrToHsv(uint8_t b, uint8_t g, uint8_t r);

// A hue x saturation histogram (the paper's HSI colour histogram without intensity, so that a
// marker keeps its signature under dim and bright lighting).
class ColourHistogram {
 public:
  static constexpr int kHueBins = 32;
  static constexpr int kSaturationBins = 16;
  static constexpr int kBins = kHueBins * kSaturationBins;

  ColourHistogram() : counts_(kBins, 0.0) {}

  // A histogram filled evenly over a hue interval (degrees, wrapping at 360) and saturation
  // interval: a starting model when no labelled frames exist.
  static ColourHistogram FromHueRange(double hue_center, double hue_half_width,
                                      double min_saturation, double max_saturation = 1.0);

  static int BinOf(double hue, double saturation);
  void Add(double hue, double saturation, double weight = 1.0);
  double total() const;
  const std::vector<double>& counts() const { return counts_; }
  // Replaces the raw counts; false (and unchanged) when the size is wrong or a count is negative
  // or not finite.
  bool SetCounts(const std::vector<double>& counts);

  // Normalised probabilities per bin, blurred over neighbouring bins (hue wraps) so that a colour
  // just outside the training samples is not a surprise; `floor` is the share of the mass spread
  // uniformly over all bins (0 for markers, small for the background so nothing has zero
  // probability). An empty histogram gives all zeros (or the uniform floor).
  std::vector<double> SmoothedProbabilities(double floor) const;

 private:
  std::vector<double> counts_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_H_
