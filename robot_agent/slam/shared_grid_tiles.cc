#include "robot_agent/slam/shared_grid_tiles.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace fleetmap {
namespace {

constexpr int kTileMask = SharedTileGrid::kTileSize - 1;
// Rays longer than this many cells come from corrupt poses; they are dropped.
constexpr int kMaxRayCells = 1 << 16;
// Tile vectors grow by this many tiles on the side that ran out, so growth is rare.
constexpr int kGrowMargin = 4;

int TileOf(int cell) { return cell >= 0 ? cell >> SharedTileGrid::kTileBits : ~((~cell) >> SharedTileGrid::kTileBits); }

}  // namespace

SharedTileGrid::SharedTileGrid(const SharedTileGridOptions& options, uint64_t owner)
    : options_(options), owner_(owner) {}

Eigen::Array2i SharedTileGrid::CellOf(const Eigen::Vector2d& point) const {
  const double r = options_.resolution;
  const double x = std::floor(point.x() / r), y = std::floor(point.y() / r);
  // Clamp so that corrupt points cannot overflow the integer conversion.
  constexpr double kLimit = 1e8;
  return Eigen::Array2i(static_cast<int>(std::clamp(x, -kLimit, kLimit)),
                        static_cast<int>(std::clamp(y, -kLimit, kLimit)));
}

const TileCell* SharedTileGrid::Cell(int x, int y) const {
  const int tx = TileOf(x) - tile_x0_, ty = TileOf(y) - tile_y0_;
  if (tx < 0 || ty < 0 || tx >= tiles_w_ || ty >= tiles_h_) return nullptr;
  const Tile* tile = tiles_[static_cast<size_t>(ty) * static_cast<size_t>(tiles_w_) + static_cast<size_t>(tx)].get();
  if (tile == nullptr) return nullptr;
  return &tile->cells[static_cast<size_t>((y & kTileMask) * kTileSize + (x & kTileMask))];
}

void SharedTileGrid::GrowToTile(int tx, int ty) {
  if (tiles_w_ > 0 && tx >= tile_x0_ && ty >= tile_y0_ && tx < tile_x0_ + tiles_w_ &&
      ty < tile_y0_ + tiles_h_) {
    return;
  }
  int x0 = tx - kGrowMargin, y0 = ty - kGrowMargin, x1 = tx + kGrowMargin + 1, y1 = ty + kGrowMargin + 1;
  if (tiles_w_ > 0) {
    x0 = std::min(x0, tile_x0_);
    y0 = std::min(y0, tile_y0_);
    x1 = std::max(x1, tile_x0_ + tiles_w_);
    y1 = std::max(y1, tile_y0_ + tiles_h_);
  }
  std::vector<std::shared_ptr<Tile>> tiles(static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0));
  for (int y = 0; y < tiles_h_; ++y) {
    for (int x = 0; x < tiles_w_; ++x) {
      tiles[static_cast<size_t>(y + tile_y0_ - y0) * static_cast<size_t>(x1 - x0) +
            static_cast<size_t>(x + tile_x0_ - x0)] =
          std::move(tiles_[static_cast<size_t>(y) * static_cast<size_t>(tiles_w_) + static_cast<size_t>(x)]);
    }
  }
  tiles_ = std::move(tiles);
  tile_x0_ = x0;
  tile_y0_ = y0;
  tiles_w_ = x1 - x0;
  tiles_h_ = y1 - y0;
}

TileCell* SharedTileGrid::MutableCell(int x, int y) {
  const int tx = TileOf(x), ty = TileOf(y);
  GrowToTile(tx, ty);
  std::shared_ptr<Tile>& slot =
      tiles_[static_cast<size_t>(ty - tile_y0_) * static_cast<size_t>(tiles_w_) + static_cast<size_t>(tx - tile_x0_)];
  if (!slot) {
    slot = std::make_shared<Tile>();
    slot->owner = owner_;
  } else if (slot->owner != owner_) {
    // Copy on write: another grid may still read the old tile.
    auto copy = std::make_shared<Tile>(*slot);
    copy->owner = owner_;
    slot = std::move(copy);
  }
  return &slot->cells[static_cast<size_t>((y & kTileMask) * kTileSize + (x & kTileMask))];
}

void SharedTileGrid::UpdateFree(int x, int y) {
  TileCell* cell = MutableCell(x, y);
  cell->log_odds = std::max(options_.log_odds_min, cell->log_odds + options_.log_odds_miss);
}

void SharedTileGrid::UpdateHit(int x, int y, const Eigen::Vector2d& point) {
  TileCell* cell = MutableCell(x, y);
  cell->log_odds = std::min(options_.log_odds_max, cell->log_odds + options_.log_odds_hit);
  const double r = options_.resolution;
  const double ox = std::clamp((point.x() / r - x - 0.5) * 65536.0, -32767.0, 32767.0);
  const double oy = std::clamp((point.y() / r - y - 0.5) * 65536.0, -32767.0, 32767.0);
  if (cell->hit_x == TileCell::kNoHit) {
    cell->hit_x = static_cast<int16_t>(ox);
    cell->hit_y = static_cast<int16_t>(oy);
  } else {
    // A slowly moving mean: later hits refine the wall position without a per-cell counter.
    cell->hit_x = static_cast<int16_t>(cell->hit_x + 0.25 * (ox - cell->hit_x));
    cell->hit_y = static_cast<int16_t>(cell->hit_y + 0.25 * (oy - cell->hit_y));
  }
}

void SharedTileGrid::InsertRays(const Eigen::Vector2d& origin, const std::vector<Eigen::Vector2d>& ends,
                                const std::vector<uint8_t>& hit) {
  const Eigen::Array2i start = CellOf(origin);
  for (size_t i = 0; i < ends.size() && i < hit.size(); ++i) {
    if (!ends[i].allFinite()) continue;
    const Eigen::Array2i end = CellOf(ends[i]);
    const int dx = std::abs(end.x() - start.x()), dy = std::abs(end.y() - start.y());
    if (std::max(dx, dy) > kMaxRayCells) continue;
    const int sx = end.x() > start.x() ? 1 : -1, sy = end.y() > start.y() ? 1 : -1;
    int x = start.x(), y = start.y();
    int error = dx - dy;
    while (x != end.x() || y != end.y()) {
      UpdateFree(x, y);
      const int e2 = 2 * error;
      if (e2 > -dy) {
        error -= dy;
        x += sx;
      }
      if (e2 < dx) {
        error += dx;
        y += sy;
      }
    }
    if (hit[i]) {
      UpdateHit(end.x(), end.y(), ends[i]);
    } else {
      UpdateFree(end.x(), end.y());
    }
  }
}

bool SharedTileGrid::NearestHit(const Eigen::Vector2d& point, int radius, Eigen::Vector2d* hit,
                                double* squared_distance) const {
  if (!point.allFinite()) return false;
  const Eigen::Array2i c = CellOf(point);
  const double r = options_.resolution;
  double best = 1e300;
  for (int y = c.y() - radius; y <= c.y() + radius; ++y) {
    for (int x = c.x() - radius; x <= c.x() + radius; ++x) {
      const TileCell* cell = Cell(x, y);
      if (cell == nullptr || cell->log_odds <= options_.occupied_log_odds || cell->hit_x == TileCell::kNoHit) {
        continue;
      }
      const Eigen::Vector2d h((x + 0.5 + cell->hit_x / 65536.0) * r, (y + 0.5 + cell->hit_y / 65536.0) * r);
      const double d2 = (h - point).squaredNorm();
      if (d2 < best) {
        best = d2;
        *hit = h;
      }
    }
  }
  if (best == 1e300) return false;
  *squared_distance = best;
  return true;
}

size_t SharedTileGrid::tile_count() const {
  size_t n = 0;
  for (const auto& tile : tiles_) n += tile ? 1 : 0;
  return n;
}

void SharedTileGrid::CollectTiles(std::unordered_set<const Tile*>* tiles) const {
  for (const auto& tile : tiles_) {
    if (tile) tiles->insert(tile.get());
  }
}

}  // namespace fleetmap
