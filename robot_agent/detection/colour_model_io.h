#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_IO_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_IO_H_

#include <string>

#include "robot_agent/detection/colour_model.h"

namespace fleetmap {

// YAML: thresholds, then `markers: [{robot_id, counts: [...]}]` and `background: {counts}`,
// each histogram as hue-major raw counts (ColourHistogram::kBins numbers).
bool WriteColourModel(const std::string& path, const ColourModel& model, std::string* error);
// False with a message naming the file and the problem; the model is validated.
bool ReadColourModel(const std::string& path, ColourModel* model, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_COLOUR_MODEL_IO_H_
