#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_CALIBRATION_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_CALIBRATION_H_

#include <map>
#include <string>
#include <vector>

#include "robot_agent/detection/colour_model.h"
#include "robot_agent/detection/image.h"
#include "robot_agent/detection/marker_detector.h"

namespace fleetmap {

// A marker's box in a labelled frame.
struct LabelledMarker {
  std::string robot_id;
  ImageBox box;
  // Only keep the box out of the background (e.g. a partly hidden marker), learn nothing from it.
  bool exclude_only = false;
};

struct CalibrationOptions {
  double inner_margin = 0.2;  // share of the box trimmed on each side before sampling the marker
  double outer_margin = 0.3;  // share of the box added on each side before sampling background
  int background_step = 2;    // sample every n-th background pixel in x and y
  double min_value = 0.08;    // skip pixels too dark to carry a hue
};

// Learns the colour model from labelled frames: marker pixels inside each labelled box go to
// that robot's histogram, the pixels well outside every box go to the background histogram.
class ColourCalibrator {
 public:
  explicit ColourCalibrator(const CalibrationOptions& options = {}) : options_(options) {}

  // False with a message when the image is unusable or a box lies outside it.
  bool AddFrame(const BgrImageView& image, const std::vector<LabelledMarker>& markers,
                std::string* error);
  // The model, markers ordered by robot id.
  ColourModel Build() const;
  int frames() const { return frames_; }
  long marker_pixels(const std::string& robot_id) const;

 private:
  const CalibrationOptions options_;
  std::map<std::string, ColourHistogram> markers_;
  ColourHistogram background_;
  int frames_ = 0;
};

// Projects a marker at `range` (camera to marker axis) and `bearing` (camera frame) into the
// image: the box of its visible silhouette, clipped to the image; empty when out of view.
ImageBox ProjectMarker(const CameraModel& camera, const MarkerGeometry& geometry, double range,
                       double bearing);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_CALIBRATION_H_
