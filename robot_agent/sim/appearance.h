#ifndef FLEETMAP_ROBOT_AGENT_SIM_APPEARANCE_H_
#define FLEETMAP_ROBOT_AGENT_SIM_APPEARANCE_H_

#include "robot_agent/sim/world.h"

namespace fleetmap::sim {

// Marker colour of the robot with 0-based index i: green for the first (as in the paper), then
// blue, orange, magenta, yellow, cyan; further robots cycle with a small hue shift.
Rgb MarkerColor(int robot_index);
// Hue in degrees [0, 360) of an RGB colour (HSV hue), for documentation and manifests.
double HueDegrees(const Rgb& color);

// Distractor colours close to the marker colours (posters, cabinets).
inline constexpr Rgb kPosterGreen{60, 175, 55};
inline constexpr Rgb kPosterBlue{55, 90, 205};
inline constexpr Rgb kPosterOrange{225, 125, 35};
inline constexpr Rgb kPosterMagenta{190, 50, 185};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_APPEARANCE_H_
