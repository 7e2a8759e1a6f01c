#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_H_

// Plain image types so that callers of the detector need no OpenCV.

#include <cstdint>
#include <vector>

namespace fleetmap {

// A non-owning view of an 8-bit, 3-channel image in B, G, R byte order (OpenCV's and the
// simulator's PNG decoding order).
struct BgrImageView {
  const uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  int stride = 0;    // bytes per row, >= 3 * width
  int channels = 3;  // anything but 3 is rejected by the detector with a message

  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
  const uint8_t* row(int y) const { return data + static_cast<long>(y) * stride; }
};

// An owning BGR image.
struct BgrImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> data;  // width * height * 3 bytes, rows packed

  BgrImage() = default;
  BgrImage(int w, int h) : width(w), height(h), data(static_cast<size_t>(w) * h * 3, 0) {}
  uint8_t* pixel(int x, int y) { return data.data() + (static_cast<size_t>(y) * width + x) * 3; }
  const uint8_t* pixel(int x, int y) const {
    return data.data() + (static_cast<size_t>(y) * width + x) * 3;
  }
  BgrImageView view() const { return {data.data(), width, height, width * 3, 3}; }
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_H_
