#include "robot_agent/sim/appearance.h"

#include <algorithm>
#include <cmath>

namespace fleetmap::sim {

Rgb MarkerColor(int robot_index) {
  static constexpr Rgb kBase[] = {{40, 190, 40},  {40, 80, 225},  {235, 130, 20},
                                  {205, 40, 205}, {220, 210, 30}, {30, 195, 205}};
  constexpr int kCount = static_cast<int>(sizeof(kBase) / sizeof(kBase[0]));
  const int index = std::max(0, robot_index);
  Rgb color = kBase[index % kCount];
  const int cycle = index / kCount;
  // Later cycles rotate the channels' balance slightly so hues stay distinct from the first six.
  color.r = static_cast<uint8_t>(std::clamp(int(color.r) + 25 * (cycle % 3), 0, 255));
  color.b = static_cast<uint8_t>(std::clamp(int(color.b) - 25 * (cycle % 3), 0, 255));
  return color;
}

double HueDegrees(const Rgb& color) {
  const double r = color.r / 255.0, g = color.g / 255.0, b = color.b / 255.0;
  const double max = std::max({r, g, b}), min = std::min({r, g, b});
  const double delta = max - min;
  if (delta <= 0.0) return 0.0;
  double hue;
  if (max == r) {
    hue = 60.0 * std::fmod((g - b) / delta, 6.0);
  } else if (max == g) {
    hue = 60.0 * ((b - r) / delta + 2.0);
  } else {
    hue = 60.0 * ((r - g) / delta + 4.0);
  }
  return hue < 0.0 ? hue + 360.0 : hue;
}

}  // namespace fleetmap::sim
