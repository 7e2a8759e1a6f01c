#include "robot_agent/detection/marker_detector.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace fleetmap {
namespace {

std::vector<std::string> RobotIds(const ColourModel& colours) {
  std::vector<std::string> ids;
  for (const MarkerColour& marker : colours.markers) ids.push_back(marker.robot_id);
  return ids;
}

}  // namespace

// Full-resolution measurements of one blob (pixel coordinates in the whole image).
struct MarkerDetector::Blob {
  int first_column = 0, last_column = 0, first_row = 0, last_row = 0;
  double center_column = 0.0;  // pixel-count weighted, sub-pixel
  double fill = 0.0;
  bool cut_left = false, cut_right = false, cut_top = false, cut_bottom = false;
};

// One run of marker-coloured columns, and its tallest part when that is narrower.
struct MarkerDetector::BlobRun {
  Blob full;
  bool has_core = false;
  Blob core;
};

std::unique_ptr<MarkerDetector> MarkerDetector::Create(const CameraModel& camera,
                                                       const MarkerGeometry& geometry,
                                                       const ColourModel& colours,
                                                       const MarkerDetectorOptions& options,
                                                       std::string* error) {
  if (!camera.IsValid(error) || !geometry.IsValid(error) || !colours.IsValid(error)) {
    return nullptr;
  }
  if (options.grid_step < 1 || options.grid_step > 16 || options.min_coarse_pixels < 1) {
    *error = "marker detector grid_step must be in [1, 16] and min_coarse_pixels >= 1";
    return nullptr;
  }
  return std::unique_ptr<MarkerDetector>(new MarkerDetector(camera, geometry, colours, options));
}

MarkerDetector::MarkerDetector(const CameraModel& camera, const MarkerGeometry& geometry,
                               const ColourModel& colours, const MarkerDetectorOptions& options)
    : camera_(camera),
      geometry_(geometry),
      options_(options),
      robot_ids_(RobotIds(colours)),
      lut_(colours) {}

bool MarkerDetector::Detect(const BgrImageView& image, std::vector<MarkerCandidate>* candidates,
                            std::string* error) const {
  candidates->clear();
  if (image.empty()) {
    *error = "empty image";
    return false;
  }
  if (image.channels != 3 || image.stride < 3 * image.width) {
    *error = "expected an 8-bit 3-channel BGR image, got " + std::to_string(image.channels) +
             " channels";
    return false;
  }
  if (image.width != camera_.width || image.height != camera_.height) {
    *error = "image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
             " but the camera model expects " + std::to_string(camera_.width) + "x" +
             std::to_string(camera_.height);
    return false;
  }
  if (lut_.num_markers() == 0) return true;

  // Stage 1: classify every grid_step-th pixel through the lookup table.
  const int step = options_.grid_step;
  const int grid_width = image.width / step, grid_height = image.height / step;
  cv::Mat labels(grid_height, grid_width, CV_8U);
  std::vector<int> label_counts(lut_.num_markers() + 1, 0);
  for (int gy = 0; gy < grid_height; ++gy) {
    const uint8_t* row = image.row(gy * step + step / 2) + 3 * (step / 2);
    uint8_t* out = labels.ptr<uint8_t>(gy);
    for (int gx = 0; gx < grid_width; ++gx) {
      const uint8_t* p = row + 3 * step * gx;
      out[gx] = lut_.Label(p[0], p[1], p[2]);
      ++label_counts[out[gx]];
    }
  }

  // Stage 2: per marker colour, clean the mask and split it into blobs.
  static const cv::Mat kKernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::Mat mask, components, stats, centroids;
  std::vector<BlobRun> runs;
  for (int label = 1; label <= lut_.num_markers(); ++label) {
    if (label_counts[label] < options_.min_coarse_pixels) continue;
    cv::compare(labels, label, mask, cv::CMP_EQ);
    // Closing fills the holes noise and highlights punch into a marker.
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, kKernel);
    const int count = cv::connectedComponentsWithStats(mask, components, stats, centroids, 8,
                                                       CV_32S);
    for (int c = 1; c < count; ++c) {
      if (stats.at<int>(c, cv::CC_STAT_AREA) < options_.min_coarse_pixels) continue;
      // Stage 3: refine at full resolution inside the blob's box plus one grid step.
      ImageBox roi;
      roi.x = std::max(0, (stats.at<int>(c, cv::CC_STAT_LEFT) - 1) * step);
      roi.y = std::max(0, (stats.at<int>(c, cv::CC_STAT_TOP) - 1) * step);
      const int right = std::min(
          image.width,
          (stats.at<int>(c, cv::CC_STAT_LEFT) + stats.at<int>(c, cv::CC_STAT_WIDTH) + 1) * step);
      const int bottom = std::min(
          image.height,
          (stats.at<int>(c, cv::CC_STAT_TOP) + stats.at<int>(c, cv::CC_STAT_HEIGHT) + 1) * step);
      // The last partial grid cell is not sampled; reach the border when the blob touches it.
      roi.width = (right >= grid_width * step ? image.width : right) - roi.x;
      roi.height = (bottom >= grid_height * step ? image.height : bottom) - roi.y;
      runs.clear();
      MeasureBlob(image, label, roi, &runs);
      for (const BlobRun& run : runs) {
        MarkerCandidate candidate;
        if (Interpret(run.full, label - 1, &candidate) ||
            (run.has_core && Interpret(run.core, label - 1, &candidate))) {
          candidates->push_back(std::move(candidate));
        }
      }
    }
  }
  return true;
}

void MarkerDetector::MeasureBlob(const BgrImageView& image, int label, const ImageBox& roi,
                                 std::vector<BlobRun>* runs) const {
  std::vector<uint8_t> mask(static_cast<size_t>(roi.width) * roi.height, 0);
  std::vector<int> column_counts(roi.width, 0);
  for (int y = 0; y < roi.height; ++y) {
    const uint8_t* p = image.row(roi.y + y) + 3 * roi.x;
    uint8_t* m = mask.data() + static_cast<size_t>(y) * roi.width;
    for (int x = 0; x < roi.width; ++x, p += 3) {
      if (lut_.Label(p[0], p[1], p[2]) == label) {
        m[x] = 1;
        ++column_counts[x];
      }
    }
  }
  const int peak = *std::max_element(column_counts.begin(), column_counts.end());
  if (peak == 0) return;
  // Columns where the counts reach a share of their peak; stray pixels of the same colour do
  // not widen a marker, and a gap splits a marker from a same-coloured poster that the coarse
  // grid's closing had merged with it.
  const int column_threshold = std::max(1, static_cast<int>(0.3 * peak));
  // Row extent, centre and fill of the columns [first, last] (ROI coordinates).
  auto make_blob = [&](int first_column, int last_column, Blob* blob) {
    std::vector<int> row_counts(roi.height, 0);
    for (int y = 0; y < roi.height; ++y) {
      const uint8_t* m = mask.data() + static_cast<size_t>(y) * roi.width;
      for (int c = first_column; c <= last_column; ++c) row_counts[y] += m[c];
    }
    double weighted = 0.0, column_total = 0.0, total = 0.0;
    for (int c = first_column; c <= last_column; ++c) {
      weighted += static_cast<double>(c) * column_counts[c];
      column_total += column_counts[c];
    }
    const int row_peak = *std::max_element(row_counts.begin(), row_counts.end());
    const int row_threshold = std::max(1, static_cast<int>(0.3 * row_peak));
    int first_row = -1, last_row = -1;
    for (int y = 0; y < roi.height; ++y) {
      if (row_counts[y] < row_threshold) continue;
      if (first_row < 0) first_row = y;
      last_row = y;
      total += row_counts[y];
    }
    if (first_row < 0 || column_total <= 0.0) return false;
    blob->first_column = roi.x + first_column;
    blob->last_column = roi.x + last_column;
    blob->first_row = roi.y + first_row;
    blob->last_row = roi.y + last_row;
    blob->center_column = roi.x + weighted / column_total;
    blob->fill = std::min(1.0, total / (static_cast<double>(last_column - first_column + 1) *
                                        (last_row - first_row + 1)));
    blob->cut_left = blob->first_column == 0;
    blob->cut_right = blob->last_column == image.width - 1;
    blob->cut_top = blob->first_row == 0;
    blob->cut_bottom = blob->last_row == image.height - 1;
    return true;
  };
  int x = 0;
  while (x < roi.width) {
    if (column_counts[x] < column_threshold) {
      ++x;
      continue;
    }
    const int first_column = x;
    int last_column = x, peak_column = x;
    while (x < roi.width && column_counts[x] >= column_threshold) {
      if (column_counts[x] > column_counts[peak_column]) peak_column = x;
      last_column = x++;
    }
    BlobRun run;
    if (!make_blob(first_column, last_column, &run.full)) continue;
    // The run's core: the tallest columns around the peak. A marker in front of a touching,
    // smaller-looking poster of its colour is the core of their merged run.
    const int core_threshold = static_cast<int>(0.75 * column_counts[peak_column]);
    int core_first = peak_column, core_last = peak_column;
    while (core_first > first_column && column_counts[core_first - 1] >= core_threshold) --core_first;
    while (core_last < last_column && column_counts[core_last + 1] >= core_threshold) ++core_last;
    if (core_first != first_column || core_last != last_column) {
      run.has_core = make_blob(core_first, core_last, &run.core);
    }
    runs->push_back(run);
  }
}

bool MarkerDetector::Interpret(const Blob& blob, int marker_index,
                               MarkerCandidate* candidate) const {
  if (blob.fill < options_.min_fill) return false;
  const double radius = geometry_.marker_radius;
  const double marker_height = geometry_.marker_height();
  const bool cut_horizontally = blob.cut_left || blob.cut_right;
  const bool cut_vertically = blob.cut_top || blob.cut_bottom;
  const double left_edge = blob.first_column - 0.5, right_edge = blob.last_column + 0.5;
  const double top_edge = blob.first_row - 0.5, bottom_edge = blob.last_row + 0.5;
  double bearing = camera_.BearingOfColumn(blob.center_column);

  // Range to the marker axis from the apparent width (angular size of a cylinder) and from the
  // apparent height (the near rim sits one radius in front of the axis).
  double range_from_width = std::numeric_limits<double>::quiet_NaN();
  double range_from_height = std::numeric_limits<double>::quiet_NaN();
  if (!cut_horizontally) {
    const double angle = camera_.BearingOfColumn(left_edge) - camera_.BearingOfColumn(right_edge);
    if (angle > 0.0) range_from_width = radius / std::sin(0.5 * angle);
  }
  if (!cut_vertically) {
    const double near_depth = camera_.fy * marker_height / (bottom_edge - top_edge);
    range_from_height = (near_depth + radius) / std::cos(bearing);
  }
  double range, size_error = 0.0;
  if (std::isfinite(range_from_width) && std::isfinite(range_from_height)) {
    size_error = std::abs(range_from_width - range_from_height) /
                 std::max(range_from_width, range_from_height);
    if (size_error > options_.size_tolerance) return false;  // wrong aspect ratio
    range = 0.5 * (range_from_width + range_from_height);
  } else if (std::isfinite(range_from_width)) {
    range = range_from_width;
  } else if (std::isfinite(range_from_height)) {
    range = range_from_height;
  } else {
    return false;  // cut on both axes: nothing to size it by
  }
  if (!(range >= options_.min_range && range <= options_.max_range)) return false;

  // A marker cut by the left or right border: its visible inner edge and expected angular
  // width place the axis.
  const double angular_width = 2.0 * std::asin(std::min(1.0, radius / range));
  if (blob.cut_left && !blob.cut_right) {
    bearing = camera_.BearingOfColumn(right_edge) + 0.5 * angular_width;
  } else if (blob.cut_right && !blob.cut_left) {
    bearing = camera_.BearingOfColumn(left_edge) - 0.5 * angular_width;
  }

  // Where the marker must appear vertically at that range (rejects same-coloured things
  // higher or lower in the scene, e.g. a poster at eye level).
  const double near_depth = range * std::cos(bearing) - radius;
  if (!(near_depth > 0.0)) return false;
  const double predicted_top = camera_.RowOfHeight(geometry_.marker_top, near_depth) - 0.5;
  const double predicted_bottom = camera_.RowOfHeight(geometry_.marker_bottom, near_depth) + 0.5;
  const double tolerance = std::max(options_.row_tolerance_pixels,
                                    options_.row_tolerance_fraction *
                                        (predicted_bottom - predicted_top));
  double row_error;
  if (!blob.cut_top && !blob.cut_bottom) {
    row_error = 0.5 * ((top_edge + bottom_edge) - (predicted_top + predicted_bottom));
  } else if (!blob.cut_top) {
    row_error = top_edge - predicted_top;
  } else if (!blob.cut_bottom) {
    row_error = bottom_edge - predicted_bottom;
  } else {
    row_error = 0.0;
  }
  if (std::abs(row_error) > tolerance) return false;

  const double size_score = std::exp(-0.5 * std::pow(size_error / options_.size_tolerance, 2));
  const double row_score = std::exp(-0.5 * std::pow(row_error / tolerance, 2));
  const double confidence = std::min(1.0, blob.fill / 0.85) * size_score * row_score *
                            (cut_horizontally || cut_vertically ? 0.8 : 1.0);
  if (confidence < options_.min_confidence) return false;

  candidate->robot_id = robot_ids_[marker_index];
  candidate->marker_index = marker_index;
  candidate->bearing_in_camera = bearing;
  candidate->angular_width = angular_width;
  candidate->apparent_width = right_edge - left_edge;
  candidate->apparent_height = bottom_edge - top_edge;
  candidate->box = {blob.first_column, blob.first_row, blob.last_column - blob.first_column + 1,
                    blob.last_row - blob.first_row + 1};
  candidate->range_from_size = range;
  candidate->position_in_robot =
      camera_.camera_in_robot * Eigen::Vector2d(range * std::cos(bearing), range * std::sin(bearing));
  candidate->truncated = cut_horizontally || cut_vertically;
  candidate->confidence = confidence;
  return true;
}

}  // namespace fleetmap
