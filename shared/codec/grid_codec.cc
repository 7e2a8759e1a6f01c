#include "shared/codec/grid_codec.h"

#include <algorithm>
#include <cmath>

#include "shared/codec/zstd_codec.h"

namespace fleetmap {
namespace {

// Float residues below this (left by adding and removing contributions) count as unknown.
constexpr float kUnknownEpsilon = 1e-3f;
// Probability cells are turned into log-odds with this scale (logit(0.999) is about 6.9).
constexpr float kProbabilityScale = 7.0f / 127.0f;
constexpr uint8_t kProbabilityUnknown = 255;

int8_t QuantizeCell(float log_odds, float scale) {
  if (!(std::abs(log_odds) >= kUnknownEpsilon)) return 0;  // also maps NaN to unknown
  const float q = std::clamp(std::round(log_odds / scale), -127.0f, 127.0f);
  if (q == 0.0f) return log_odds > 0.0f ? 1 : -1;  // observed stays observed
  return static_cast<int8_t>(q);
}

bool Fail(GridDecodeError kind, const std::string& message, GridDecodeError* code,
          std::string* error) {
  *code = kind;
  *error = message;
  return false;
}

}  // namespace

QuantizedGrid Quantize(const OccupancyGrid& grid, float log_odds_limit, bool crop_to_known) {
  QuantizedGrid out;
  out.log_odds_scale = log_odds_limit / 127.0f;
  out.geometry.resolution = grid.resolution();
  CellIndex lo(0, 0), hi(grid.width() - 1, grid.height() - 1);
  if (crop_to_known && !grid.KnownBounds(&lo, &hi)) {
    out.geometry.origin = grid.origin();
    return out;
  }
  if (grid.empty()) {
    out.geometry.origin = grid.origin();
    return out;
  }
  out.geometry.width = hi.x() - lo.x() + 1;
  out.geometry.height = hi.y() - lo.y() + 1;
  out.geometry.origin = grid.origin() + grid.resolution() * lo.cast<double>().matrix();
  out.cells.resize(static_cast<size_t>(out.geometry.cells()));
  const std::vector<float>& src = grid.log_odds();
  for (int y = 0; y < out.geometry.height; ++y) {
    const size_t src_row = static_cast<size_t>(y + lo.y()) * grid.width() + lo.x();
    const size_t dst_row = static_cast<size_t>(y) * out.geometry.width;
    for (int x = 0; x < out.geometry.width; ++x) {
      out.cells[dst_row + x] = QuantizeCell(src[src_row + x], out.log_odds_scale);
    }
  }
  return out;
}

OccupancyGrid Dequantize(const QuantizedGrid& grid, const OccupancyGridOptions& options) {
  OccupancyGridOptions grid_options = options;
  grid_options.resolution = grid.geometry.resolution;
  OccupancyGrid out(grid_options, grid.geometry.origin, grid.geometry.width,
                    grid.geometry.height);
  for (int y = 0; y < grid.geometry.height; ++y) {
    for (int x = 0; x < grid.geometry.width; ++x) {
      const int8_t v = grid.cells[static_cast<size_t>(y) * grid.geometry.width + x];
      if (v != 0) out.SetLogOdds(CellIndex(x, y), v * grid.log_odds_scale);
    }
  }
  return out;
}

EncodedGrid Compress(const QuantizedGrid& grid, int zstd_level) {
  EncodedGrid out;
  out.geometry = grid.geometry;
  out.encoding = CellEncoding::kLogOddsInt8;
  out.log_odds_scale = grid.log_odds_scale;
  out.compressed = ZstdCompress(grid.cells.data(), grid.cells.size(), zstd_level);
  return out;
}

bool Decompress(const EncodedGrid& encoded, const GridLimits& limits, QuantizedGrid* grid,
                GridDecodeError* code, std::string* error) {
  const GridGeometry& g = encoded.geometry;
  *code = GridDecodeError::kNone;
  if (g.width < 0 || g.height < 0) {
    return Fail(GridDecodeError::kInvalid, "grid width and height must not be negative", code,
                error);
  }
  if (g.width > limits.max_side || g.height > limits.max_side || g.cells() > limits.max_cells) {
    return Fail(GridDecodeError::kTooLarge,
                "grid of " + std::to_string(g.width) + " x " + std::to_string(g.height) +
                    " cells exceeds the limit (" + std::to_string(limits.max_side) +
                    " per side, " + std::to_string(limits.max_cells) + " in all)",
                code, error);
  }
  if (!std::isfinite(g.resolution) || g.resolution < limits.min_resolution ||
      g.resolution > limits.max_resolution) {
    return Fail(GridDecodeError::kInvalid,
                "grid resolution " + std::to_string(g.resolution) + " m is outside [" +
                    std::to_string(limits.min_resolution) + ", " +
                    std::to_string(limits.max_resolution) + "]",
                code, error);
  }
  if (!g.origin.allFinite() || g.origin.cwiseAbs().maxCoeff() > limits.max_abs_origin) {
    return Fail(GridDecodeError::kInvalid, "grid origin is not finite or absurdly far", code,
                error);
  }
  const bool int8 = encoded.encoding == CellEncoding::kLogOddsInt8;
  if (!int8 && encoded.encoding != CellEncoding::kProbabilityUint8) {
    return Fail(GridDecodeError::kInvalid, "unknown cell encoding", code, error);
  }
  if (int8 && !(encoded.log_odds_scale > 0.0f && encoded.log_odds_scale <= 1.0f)) {
    return Fail(GridDecodeError::kInvalid, "log_odds_scale must be in (0, 1]", code, error);
  }
  std::string raw;
  std::string zstd_error;
  if (!ZstdDecompress(encoded.compressed, static_cast<size_t>(g.cells()), &raw, &zstd_error)) {
    return Fail(GridDecodeError::kInvalid, "grid cells: " + zstd_error, code, error);
  }
  grid->geometry = g;
  grid->cells.resize(raw.size());
  if (int8) {
    grid->log_odds_scale = encoded.log_odds_scale;
    std::copy(raw.begin(), raw.end(), reinterpret_cast<char*>(grid->cells.data()));
    return true;
  }
  grid->log_odds_scale = kProbabilityScale;
  for (size_t i = 0; i < raw.size(); ++i) {
    const uint8_t v = static_cast<uint8_t>(raw[i]);
    if (v == kProbabilityUnknown) {
      grid->cells[i] = 0;
      continue;
    }
    const float p = std::clamp(v / 254.0f, 0.001f, 0.999f);
    grid->cells[i] = QuantizeCell(std::log(p / (1.0f - p)), kProbabilityScale);
  }
  return true;
}

EncodedGrid EncodeGrid(const OccupancyGrid& grid, int zstd_level) {
  const float limit = std::max(std::abs(grid.options().log_odds_min),
                               std::abs(grid.options().log_odds_max));
  return Compress(Quantize(grid, limit > 0.0f ? limit : 4.0f, /*crop_to_known=*/true), zstd_level);
}

bool DecodeGrid(const EncodedGrid& encoded, const GridLimits& limits,
                const OccupancyGridOptions& options, OccupancyGrid* grid, GridDecodeError* code,
                std::string* error) {
  QuantizedGrid quantized;
  if (!Decompress(encoded, limits, &quantized, code, error)) return false;
  *grid = Dequantize(quantized, options);
  return true;
}

}  // namespace fleetmap
