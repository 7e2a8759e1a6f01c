#ifndef FLEETMAP_SHARED_CODEC_GRID_CODEC_H_
#define FLEETMAP_SHARED_CODEC_GRID_CODEC_H_

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "shared/core/occupancy_grid.h"

namespace fleetmap {

// Where a grid's cells lie: cell (0, 0) has its lower-left corner at `origin`, rows go up +y.
struct GridGeometry {
  int width = 0;
  int height = 0;
  double resolution = 0.05;  // metres per cell
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  int64_t cells() const { return static_cast<int64_t>(width) * static_cast<int64_t>(height); }
};

// Compact cells: int8 log-odds, value * log_odds_scale = log-odds, 0 = never observed.
// The form a published global map version is held in memory and served from.
struct QuantizedGrid {
  GridGeometry geometry;
  float log_odds_scale = 4.0f / 127.0f;
  std::vector<int8_t> cells;  // row-major, index = y * width + x
};

enum class CellEncoding {
  kLogOddsInt8 = 1,       // int8 cells, value * scale = log-odds, 0 unknown
  kProbabilityUint8 = 2,  // uint8 cells, 0..254 = probability * 254, 255 unknown
};

// A grid as it travels and is stored: row-major cells in one zstd frame.
struct EncodedGrid {
  GridGeometry geometry;
  CellEncoding encoding = CellEncoding::kLogOddsInt8;
  float log_odds_scale = 4.0f / 127.0f;  // only for kLogOddsInt8
  std::string compressed;
};

// What a decoder accepts; anything beyond is refused before allocating.
struct GridLimits {
  int max_side = 20000;               // cells along x or y
  int64_t max_cells = 64LL << 20;     // width * height
  double min_resolution = 0.001;      // metres
  double max_resolution = 100.0;
  double max_abs_origin = 1e7;        // metres
};

enum class GridDecodeError { kNone, kInvalid, kTooLarge };

// Quantizes a float log-odds grid; values are clamped to +-`log_odds_limit`. With
// `crop_to_known` only the box of observed cells is kept.
QuantizedGrid Quantize(const OccupancyGrid& grid, float log_odds_limit, bool crop_to_known);
// Back to a float grid with `options` (its resolution is replaced by the grid's).
OccupancyGrid Dequantize(const QuantizedGrid& grid,
                         const OccupancyGridOptions& options = OccupancyGridOptions());

EncodedGrid Compress(const QuantizedGrid& grid, int zstd_level = 1);
// Checks geometry against `limits`, then decompresses; never crashes on hostile input.
bool Decompress(const EncodedGrid& encoded, const GridLimits& limits, QuantizedGrid* grid,
                GridDecodeError* code, std::string* error);

// Convenience: OccupancyGrid <-> EncodedGrid (int8 log-odds, cropped to observed cells).
EncodedGrid EncodeGrid(const OccupancyGrid& grid, int zstd_level = 1);
bool DecodeGrid(const EncodedGrid& encoded, const GridLimits& limits,
                const OccupancyGridOptions& options, OccupancyGrid* grid, GridDecodeError* code,
                std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CODEC_GRID_CODEC_H_
