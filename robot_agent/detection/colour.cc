#include "robot_agent/detection/colour.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

Hsv BgrToHsv(uint8_t b, uint8_t g, uint8_t r) {
  const double rf = r / 255.0, gf = g / 255.0, bf = b / 255.0;
  const double max = std::max({rf, gf, bf});
  const double min = std::min({rf, gf, bf});
  const double delta = max - min;
  Hsv hsv;
  hsv.value = max;
  hsv.saturation = max > 0.0 ? delta / max : 0.0;
  if (delta <= 0.0) return hsv;
  double hue;
  if (max == rf) {
    hue = 60.0 * (gf - bf) / delta;
  } else if (max == gf) {
    hue = 60.0 * (bf - rf) / delta + 120.0;
  } else {
    hue = 60.0 * (rf - gf) / delta + 240.0;
  }
  if (hue < 0.0) hue += 360.0;
  if (hue >= 360.0) hue -= 360.0;
  hsv.hue = hue;
  return hsv;
}

int ColourHistogram::BinOf(double hue, double saturation) {
  int h = static_cast<int>(std::floor(hue / 360.0 * kHueBins));
  h = ((h % kHueBins) + kHueBins) % kHueBins;
  const int s = std::clamp(static_cast<int>(saturation * kSaturationBins), 0, kSaturationBins - 1);
  return h * kSaturationBins + s;
}

ColourHistogram ColourHistogram::FromHueRange(double hue_center, double hue_half_width,
                                              double min_saturation, double max_saturation) {
  ColourHistogram histogram;
  // Sample densely so every bin the interval touches receives mass.
  for (double dh = -hue_half_width; dh <= hue_half_width; dh += 0.5) {
    double hue = std::fmod(hue_center + dh, 360.0);
    if (hue < 0.0) hue += 360.0;
    for (double s = min_saturation; s <= max_saturation; s += 0.01) histogram.Add(hue, s);
  }
  return histogram;
}

void ColourHistogram::Add(double hue, double saturation, double weight) {
  counts_[BinOf(hue, saturation)] += weight;
}

double ColourHistogram::total() const {
  double sum = 0.0;
  for (double c : counts_) sum += c;
  return sum;
}

bool ColourHistogram::SetCounts(const std::vector<double>& counts) {
  if (counts.size() != static_cast<size_t>(kBins)) return false;
  for (double c : counts) {
    if (!std::isfinite(c) || c < 0.0) return false;
  }
  counts_ = counts;
  return true;
}

std::vector<double> ColourHistogram::SmoothedProbabilities(double floor) const {
  // Separable [1 2 1] / 4 blur; hue is circular, saturation is clamped at its ends.
  std::vector<double> blurred(kBins, 0.0);
  for (int h = 0; h < kHueBins; ++h) {
    for (int s = 0; s < kSaturationBins; ++s) {
      double sum = 0.0;
      for (int dh = -1; dh <= 1; ++dh) {
        const int hh = (h + dh + kHueBins) % kHueBins;
        for (int ds = -1; ds <= 1; ++ds) {
          const int ss = std::clamp(s + ds, 0, kSaturationBins - 1);
          sum += (dh == 0 ? 2.0 : 1.0) * (ds == 0 ? 2.0 : 1.0) * counts_[hh * kSaturationBins + ss];
        }
      }
      blurred[h * kSaturationBins + s] = sum / 16.0;
    }
  }
  double total = 0.0;
  for (double b : blurred) total += b;
  std::vector<double> probabilities(kBins, floor / kBins);
  if (total <= 0.0) return probabilities;
  for (int i = 0; i < kBins; ++i) probabilities[i] += (1.0 - floor) * blurred[i] / total;
  return probabilities;
}

}  // namespace fleetmap
