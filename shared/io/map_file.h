#ifndef FLEETMAP_SHARED_IO_MAP_FILE_H_
#define FLEETMAP_SHARED_IO_MAP_FILE_H_

#include <string>

#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// The metadata of a ROS map_server map (the YAML beside the image).
struct MapMetadata {
  std::string image;  // relative to the YAML's folder
  double resolution = 0.05;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  // lower-left pixel's corner, metres
  double origin_yaw = 0.0;                           // must be 0 for us (ROS ignores it too)
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
};

// Reads a ROS map_server map (YAML + PGM or PNG image, 8-bit grey) into a grid in "trinary"
// mode: pixels darker than occupied_thresh become occupied (log_odds_max), lighter than
// free_thresh free (log_odds_min), the rest unknown. Fills `error` on a missing file, a bad
// YAML field or an unreadable image.
bool ReadMap(const std::string& yaml_path, OccupancyGrid* grid, std::string* error);

// Writes `<stem>.pgm` and `<stem>.yaml` (ROS map_server format: 254 free, 0 occupied, 205
// unknown). Writes only the observed part of the grid when `crop` is true.
bool WriteMap(const std::string& stem, const OccupancyGrid& grid, std::string* error,
              bool crop = true);

// Writes a PNG picture of the grid (white free, black occupied, grey unknown).
bool WriteMapPng(const std::string& path, const OccupancyGrid& grid, std::string* error,
                 bool crop = true);

// An 8-bit grey image, row 0 at the top (the map's +y edge).
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;
};
bool ReadPgm(const std::string& path, GreyImage* image, std::string* error);
bool WritePgm(const std::string& path, const GreyImage& image, std::string* error);
bool ReadPng(const std::string& path, GreyImage* image, std::string* error);
// Writes 8-bit grey (channels = 1) or RGB (channels = 3) pixels, rows top to bottom.
bool WritePng(const std::string& path, int width, int height, int channels,
              const std::vector<uint8_t>& pixels, std::string* error);

// Grid <-> image conversions in map_server's convention (used by the files above and by tools).
GreyImage GridToImage(const OccupancyGrid& grid, bool crop, Eigen::Vector2d* image_origin);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_IO_MAP_FILE_H_
