#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_MARKER_DETECTOR_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_MARKER_DETECTOR_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "robot_agent/detection/camera_model.h"
#include "robot_agent/detection/colour_model.h"
#include "robot_agent/detection/image.h"

namespace fleetmap {

struct ImageBox {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

// A marker found in one image, before the laser has confirmed it.
struct MarkerCandidate {
  std::string robot_id;
  int marker_index = 0;            // index in the colour model
  double bearing_in_camera = 0.0;  // radians, + left, of the marker's axis
  double angular_width = 0.0;      // radians, expected full width of the marker at its range
  double apparent_width = 0.0;     // pixels, visible part
  double apparent_height = 0.0;    // pixels, visible part
  ImageBox box;                    // visible part, full-resolution pixels
  double range_from_size = 0.0;    // metres from the camera to the marker axis, from its size
  // Rough marker position in the robot frame (from bearing and size range); the laser refines it.
  Eigen::Vector2d position_in_robot = Eigen::Vector2d::Zero();
  bool truncated = false;          // cut by the image border
  double confidence = 0.0;         // [0, 1]: fill, size consistency, truncation
};

struct MarkerDetectorOptions {
  int grid_step = 4;            // coarse classification grid, pixels
  int min_coarse_pixels = 3;    // smallest blob on the coarse grid
  double min_range = 0.3;       // metres
  double max_range = 10.0;
  // Largest relative disagreement between the ranges implied by the marker's apparent width and
  // by its apparent height (a cylinder's aspect ratio).
  double size_tolerance = 0.35;
  // Allowed distance between the observed and predicted vertical centre of the marker.
  double row_tolerance_pixels = 4.0;
  double row_tolerance_fraction = 0.35;  // of the apparent height
  double min_fill = 0.45;       // marker pixels / box area
  double min_confidence = 0.15;
};

// Finds coloured markers in a BGR image: LUT colour classification on a coarse grid, morphology,
// connected components, then full-resolution refinement inside each blob and shape/size checks
// against the known marker geometry and camera intrinsics.
class MarkerDetector {
 public:
  // Returns nullptr with a message when the camera, geometry or colour model is invalid.
  static std::unique_ptr<MarkerDetector> Create(const CameraModel& camera,
                                                const MarkerGeometry& geometry,
                                                const ColourModel& colours,
                                                const MarkerDetectorOptions& options,
                                                std::string* error);

  // False with a message for an unusable image (empty, wrong size, wrong channel count); true
  // with zero or more candidates otherwise.
  bool Detect(const BgrImageView& image, std::vector<MarkerCandidate>* candidates,
              std::string* error) const;

  const CameraModel& camera() const { return camera_; }
  const MarkerGeometry& geometry() const { return geometry_; }

 private:
  MarkerDetector(const CameraModel& camera, const MarkerGeometry& geometry,
                 const ColourModel& colours, const MarkerDetectorOptions& options);

  struct Blob;
  struct BlobRun;
  // Full-resolution measurement inside `roi`, per run of marker-coloured columns.
  void MeasureBlob(const BgrImageView& image, int label, const ImageBox& roi,
                   std::vector<BlobRun>* runs) const;
  bool Interpret(const Blob& blob, int marker_index, MarkerCandidate* candidate) const;

  const CameraModel camera_;
  const MarkerGeometry geometry_;
  const MarkerDetectorOptions options_;
  const std::vector<std::string> robot_ids_;
  const ColourLut lut_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_MARKER_DETECTOR_H_
