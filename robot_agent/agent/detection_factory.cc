#include "robot_agent/agent/detection_factory.h"

#include "robot_agent/detection/colour_model_io.h"
#ifdef FLEETMAP_AGENT_HAVE_SIM
#include "robot_agent/agent/sim_detection_setup.h"
#include "robot_agent/agent/sim_source.h"
#endif

namespace fleetmap {

ColourModel ColourModelFromHues(const std::map<std::string, double>& hues, double half_width,
                                double min_saturation) {
  ColourModel model;
  for (const auto& [robot, hue] : hues) {
    model.markers.push_back(
        {robot, ColourHistogram::FromHueRange(hue, half_width, min_saturation)});
  }
  return model;
}

std::unique_ptr<DetectionStage> CreateDetectionStage(const AgentConfig& config,
                                                     const SensorSource& source,
                                                     std::string* error) {
  const DetectionConfig& detection = config.detection;
  DetectionSetup setup;
  bool from_simulator = false;
#ifdef FLEETMAP_AGENT_HAVE_SIM
  if (const auto* sim = dynamic_cast<const SimSource*>(&source)) {
    SimColourLearningOptions learning;
    learning.views = detection.learn_views;
    std::string why;
    if (!MakeSimDetectionSetup(sim->simulation(), learning, &setup, &why)) {
      *error = "detection: " + why;
      return nullptr;
    }
    from_simulator = true;
  }
#endif
  if (!from_simulator) {
    setup.camera = detection.camera;
    setup.geometry = detection.marker;
    setup.laser_range_noise = detection.laser_range_noise;
  }
  if (!detection.colour_model.empty()) {
    std::string why;
    if (!ReadColourModel(detection.colour_model, &setup.colours, &why)) {
      *error = "detection.colour_model: " + why;
      return nullptr;
    }
  } else if (!detection.marker_hues.empty()) {
    setup.colours = ColourModelFromHues(detection.marker_hues, detection.hue_half_width,
                                        detection.min_saturation);
  } else if (!from_simulator) {
    *error = "detection: no marker colours (colour_model or marker_hues) for " + source.Describe();
    return nullptr;
  }
  DetectionStageOptions options;
  options.observer_id = config.robot_id;
  options.max_time_difference = detection.max_time_difference;
  options.robot_ids = detection.robot_ids;
  return DetectionStage::Create(setup, options, error);
}

}  // namespace fleetmap
