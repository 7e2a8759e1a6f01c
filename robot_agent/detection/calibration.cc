#include "robot_agent/detection/calibration.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

bool ColourCalibrator::AddFrame(const BgrImageView& image,
                                const std::vector<LabelledMarker>& markers, std::string* error) {
  if (image.empty() || image.channels != 3 || image.stride < 3 * image.width) {
    *error = "calibration needs a non-empty 8-bit BGR image";
    return false;
  }
  for (const LabelledMarker& marker : markers) {
    const ImageBox& b = marker.box;
    if (marker.robot_id.empty() || b.width <= 0 || b.height <= 0 || b.x < 0 || b.y < 0 ||
        b.x + b.width > image.width || b.y + b.height > image.height) {
      *error = "labelled box of robot '" + marker.robot_id + "' lies outside the image";
      return false;
    }
  }
  // Background excludes each box grown by the outer margin.
  std::vector<uint8_t> excluded(static_cast<size_t>(image.width) * image.height, 0);
  for (const LabelledMarker& marker : markers) {
    const ImageBox& b = marker.box;
    const int mx = static_cast<int>(std::ceil(options_.outer_margin * b.width)) + 1;
    const int my = static_cast<int>(std::ceil(options_.outer_margin * b.height)) + 1;
    for (int y = std::max(0, b.y - my); y < std::min(image.height, b.y + b.height + my); ++y) {
      for (int x = std::max(0, b.x - mx); x < std::min(image.width, b.x + b.width + mx); ++x) {
        excluded[static_cast<size_t>(y) * image.width + x] = 1;
      }
    }
  }
  const int step = std::max(1, options_.background_step);
  for (int y = 0; y < image.height; y += step) {
    const uint8_t* row = image.row(y);
    for (int x = 0; x < image.width; x += step) {
      if (excluded[static_cast<size_t>(y) * image.width + x]) continue;
      const Hsv hsv = BgrToHsv(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
      if (hsv.value >= options_.min_value) background_.Add(hsv.hue, hsv.saturation);
    }
  }
  for (const LabelledMarker& marker : markers) {
    if (marker.exclude_only) continue;
    const ImageBox& b = marker.box;
    const int mx = static_cast<int>(options_.inner_margin * b.width);
    const int my = static_cast<int>(options_.inner_margin * b.height);
    ColourHistogram& histogram = markers_[marker.robot_id];
    for (int y = b.y + my; y < b.y + b.height - my; ++y) {
      const uint8_t* row = image.row(y);
      for (int x = b.x + mx; x < b.x + b.width - mx; ++x) {
        const Hsv hsv = BgrToHsv(row[3 * x], row[3 * x + 1], row[3 * x + 2]);
        if (hsv.value >= options_.min_value) histogram.Add(hsv.hue, hsv.saturation);
      }
    }
  }
  ++frames_;
  return true;
}

ColourModel ColourCalibrator::Build() const {
  ColourModel model;
  for (const auto& [robot_id, histogram] : markers_) {
    if (histogram.total() > 0.0) model.markers.push_back({robot_id, histogram});
  }
  model.background = background_;
  model.min_value = options_.min_value;
  return model;
}

long ColourCalibrator::marker_pixels(const std::string& robot_id) const {
  const auto it = markers_.find(robot_id);
  return it == markers_.end() ? 0 : static_cast<long>(it->second.total());
}

ImageBox ProjectMarker(const CameraModel& camera, const MarkerGeometry& geometry, double range,
                       double bearing) {
  const double r = geometry.marker_radius;
  if (!(range > r) || std::abs(bearing) >= 0.5 * M_PI) return {};
  const double half_angle = std::asin(r / range);
  const double left = camera.ColumnOfBearing(bearing + half_angle);
  const double right = camera.ColumnOfBearing(bearing - half_angle);
  const double near_depth = range * std::cos(bearing) - r;
  if (!(near_depth > 0.0)) return {};
  const double top = camera.RowOfHeight(geometry.marker_top, near_depth);
  const double bottom = camera.RowOfHeight(geometry.marker_bottom, near_depth);
  const int x0 = std::max(0, static_cast<int>(std::ceil(left - 0.5)));
  const int x1 = std::min(camera.width - 1, static_cast<int>(std::floor(right + 0.5)) - 1);
  const int y0 = std::max(0, static_cast<int>(std::ceil(top - 0.5)));
  const int y1 = std::min(camera.height - 1, static_cast<int>(std::floor(bottom + 0.5)) - 1);
  if (x1 < x0 || y1 < y0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

}  // namespace fleetmap
