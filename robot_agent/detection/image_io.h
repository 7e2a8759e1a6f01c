#ifndef FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_IO_H_
#define FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_IO_H_

#include <string>

#include "robot_agent/detection/image.h"

namespace fleetmap {

// Reads a PNG/JPEG/PPM colour image (grey images are expanded to BGR). False with a message on
// a missing or undecodable file.
bool ReadBgrImage(const std::string& path, BgrImage* image, std::string* error);
// Writes an image; the format follows the extension (.png recommended).
bool WriteBgrImage(const std::string& path, const BgrImage& image, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_DETECTION_IMAGE_IO_H_
