#include "robot_agent/detection/image_io.h"

#include <cstring>
#include <exception>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace fleetmap {

bool ReadBgrImage(const std::string& path, BgrImage* image, std::string* error) {
  cv::Mat mat;
  try {
    mat = cv::imread(path, cv::IMREAD_COLOR);
  } catch (const std::exception& e) {
    *error = path + ": cannot decode image: " + e.what();
    return false;
  }
  if (mat.empty() || mat.type() != CV_8UC3) {
    *error = path + ": cannot read image (missing file or unsupported format)";
    return false;
  }
  *image = BgrImage(mat.cols, mat.rows);
  for (int y = 0; y < mat.rows; ++y) {
    std::memcpy(image->pixel(0, y), mat.ptr<uint8_t>(y), static_cast<size_t>(mat.cols) * 3);
  }
  return true;
}

bool WriteBgrImage(const std::string& path, const BgrImage& image, std::string* error) {
  if (image.width <= 0 || image.height <= 0 ||
      image.data.size() != static_cast<size_t>(image.width) * image.height * 3) {
    *error = path + ": refusing to write an empty or inconsistent image";
    return false;
  }
  const cv::Mat mat(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.data.data()));
  try {
    if (!cv::imwrite(path, mat)) {
      *error = path + ": cannot write image";
      return false;
    }
  } catch (const std::exception& e) {
    *error = path + ": cannot write image: " + e.what();
    return false;
  }
  return true;
}

}  // namespace fleetmap
