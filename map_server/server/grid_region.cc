#include "map_server/server/grid_region.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

int8_t Combine(int8_t current, int8_t value) {
  if (current == 0) return value;
  if (value == 0) return current;
  if (current > 0 || value > 0) return std::max(current, value);
  return std::min(current, value);
}

bool Fail(RegionError kind, const std::string& message, RegionError* code, std::string* error) {
  *code = kind;
  *error = message;
  return false;
}

}  // namespace

bool ExtractRegion(const QuantizedGrid& map, const RegionQuery& query, QuantizedGrid* region,
                   RegionError* code, std::string* error) {
  *code = RegionError::kNone;
  const GridGeometry& g = map.geometry;
  const double r = query.resolution > 0.0 ? query.resolution : g.resolution;
  if (!std::isfinite(query.resolution) || query.resolution < 0.0 ||
      (query.resolution > 0.0 && (r < 0.001 || r > 100.0))) {
    return Fail(RegionError::kInvalid, "resolution must be 0 (native) or in [0.001, 100] m", code,
                error);
  }
  Eigen::Vector2d lo = g.origin;
  Eigen::Vector2d hi = g.origin + g.resolution * Eigen::Vector2d(g.width, g.height);
  if (query.box) {
    const auto& [bmin, bmax] = *query.box;
    if (!bmin.allFinite() || !bmax.allFinite() || bmin.x() >= bmax.x() || bmin.y() >= bmax.y()) {
      return Fail(RegionError::kInvalid, "bbox must be finite with min < max", code, error);
    }
    lo = lo.cwiseMax(bmin);
    hi = hi.cwiseMin(bmax);
  }
  region->log_odds_scale = map.log_odds_scale;
  region->geometry = GridGeometry();
  region->geometry.resolution = r;
  region->cells.clear();
  if (g.cells() == 0 || lo.x() >= hi.x() || lo.y() >= hi.y()) {
    region->geometry.origin = lo;
    return true;
  }
  // Snap the lower corner onto the map's cell boundaries, so native crops are exact.
  const Eigen::Vector2d first_cell = ((lo - g.origin) / g.resolution).array().floor().matrix();
  const Eigen::Vector2d origin = g.origin + g.resolution * first_cell;
  const double w = std::ceil((hi.x() - origin.x()) / r - 1e-9);
  const double h = std::ceil((hi.y() - origin.y()) / r - 1e-9);
  if (w * h > static_cast<double>(query.max_cells)) {
    return Fail(RegionError::kTooLarge,
                "the answer would have " + std::to_string(static_cast<int64_t>(w * h)) +
                    " cells, more than the limit of " + std::to_string(query.max_cells) +
                    "; ask for a smaller box or a coarser resolution",
                code, error);
  }
  GridGeometry& out = region->geometry;
  out.origin = origin;
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  region->cells.assign(static_cast<size_t>(out.cells()), 0);
  const int x0 = static_cast<int>(first_cell.x());
  const int y0 = static_cast<int>(first_cell.y());
  if (r >= g.resolution) {
    // Each map cell inside the region lands in one output cell.
    const int x1 = std::min(g.width, static_cast<int>(std::ceil((hi.x() - g.origin.x()) / g.resolution)));
    const int y1 = std::min(g.height, static_cast<int>(std::ceil((hi.y() - g.origin.y()) / g.resolution)));
    const double ratio = g.resolution / r;
    for (int y = y0; y < y1; ++y) {
      const int oy = std::min(out.height - 1, static_cast<int>(((y - y0) + 0.5) * ratio));
      const int8_t* row = map.cells.data() + static_cast<size_t>(y) * g.width;
      int8_t* out_row = region->cells.data() + static_cast<size_t>(oy) * out.width;
      for (int x = x0; x < x1; ++x) {
        if (row[x] == 0) continue;
        const int ox = std::min(out.width - 1, static_cast<int>(((x - x0) + 0.5) * ratio));
        out_row[ox] = Combine(out_row[ox], row[x]);
      }
    }
    return true;
  }
  // Finer than the map: each output cell takes the map cell under its centre.
  for (int oy = 0; oy < out.height; ++oy) {
    const int y = static_cast<int>(std::floor((origin.y() + (oy + 0.5) * r - g.origin.y()) / g.resolution));
    if (y < 0 || y >= g.height) continue;
    for (int ox = 0; ox < out.width; ++ox) {
      const int x = static_cast<int>(std::floor((origin.x() + (ox + 0.5) * r - g.origin.x()) / g.resolution));
      if (x < 0 || x >= g.width) continue;
      region->cells[static_cast<size_t>(oy) * out.width + ox] =
          map.cells[static_cast<size_t>(y) * g.width + x];
    }
  }
  return true;
}

}  // namespace fleetmap
