#include "robot_agent/detection/colour_model_io.h"

#include <exception>
#include <fstream>

#include <yaml-cpp/yaml.h>

namespace fleetmap {
namespace {

void EmitHistogram(const ColourHistogram& histogram, YAML::Emitter* out) {
  *out << YAML::Key << "counts" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (double c : histogram.counts()) *out << c;
  *out << YAML::EndSeq;
}

bool ParseHistogram(const YAML::Node& node, ColourHistogram* histogram, std::string* error) {
  if (!node || !node["counts"] || !node["counts"].IsSequence()) {
    *error = "histogram without a 'counts' list";
    return false;
  }
  const std::vector<double> counts = node["counts"].as<std::vector<double>>();
  if (!histogram->SetCounts(counts)) {
    *error = "histogram needs " + std::to_string(ColourHistogram::kBins) +
             " non-negative counts, found " + std::to_string(counts.size());
    return false;
  }
  return true;
}

}  // namespace

bool WriteColourModel(const std::string& path, const ColourModel& model, std::string* error) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "hue_bins" << YAML::Value << ColourHistogram::kHueBins;
  out << YAML::Key << "saturation_bins" << YAML::Value << ColourHistogram::kSaturationBins;
  out << YAML::Key << "min_value" << YAML::Value << model.min_value;
  out << YAML::Key << "min_likelihood_ratio" << YAML::Value << model.min_likelihood_ratio;
  out << YAML::Key << "min_marker_probability" << YAML::Value << model.min_marker_probability;
  out << YAML::Key << "background_floor" << YAML::Value << model.background_floor;
  out << YAML::Key << "markers" << YAML::Value << YAML::BeginSeq;
  for (const MarkerColour& marker : model.markers) {
    out << YAML::BeginMap << YAML::Key << "robot_id" << YAML::Value << marker.robot_id;
    EmitHistogram(marker.histogram, &out);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "background" << YAML::Value << YAML::BeginMap;
  EmitHistogram(model.background, &out);
  out << YAML::EndMap << YAML::EndMap;
  std::ofstream file(path);
  file << out.c_str() << "\n";
  if (!file) {
    *error = path + ": cannot write colour model";
    return false;
  }
  return true;
}

bool ReadColourModel(const std::string& path, ColourModel* model, std::string* error) {
  try {
    const YAML::Node root = YAML::LoadFile(path);
    if (!root.IsMap()) {
      *error = path + ": not a colour model (expected a YAML map)";
      return false;
    }
    if (root["hue_bins"].as<int>(-1) != ColourHistogram::kHueBins ||
        root["saturation_bins"].as<int>(-1) != ColourHistogram::kSaturationBins) {
      *error = path + ": histogram size differs from this build's " +
               std::to_string(ColourHistogram::kHueBins) + "x" +
               std::to_string(ColourHistogram::kSaturationBins);
      return false;
    }
    ColourModel result;
    result.min_value = root["min_value"].as<double>(result.min_value);
    result.min_likelihood_ratio =
        root["min_likelihood_ratio"].as<double>(result.min_likelihood_ratio);
    result.min_marker_probability =
        root["min_marker_probability"].as<double>(result.min_marker_probability);
    result.background_floor = root["background_floor"].as<double>(result.background_floor);
    if (root["markers"] && !root["markers"].IsSequence()) {
      *error = path + ": 'markers' must be a list";
      return false;
    }
    for (const YAML::Node& node : root["markers"]) {
      MarkerColour marker;
      marker.robot_id = node["robot_id"].as<std::string>("");
      std::string what;
      if (!ParseHistogram(node, &marker.histogram, &what)) {
        *error = path + ": marker '" + marker.robot_id + "': " + what;
        return false;
      }
      result.markers.push_back(std::move(marker));
    }
    std::string what;
    if (!ParseHistogram(root["background"], &result.background, &what)) {
      *error = path + ": background: " + what;
      return false;
    }
    if (!result.IsValid(&what)) {
      *error = path + ": " + what;
      return false;
    }
    *model = std::move(result);
    return true;
  } catch (const std::exception& e) {
    *error = path + ": cannot read colour model: " + e.what();
    return false;
  }
}

}  // namespace fleetmap
