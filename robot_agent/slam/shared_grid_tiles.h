#ifndef FLEETMAP_ROBOT_AGENT_SLAM_SHARED_GRID_TILES_H_
#define FLEETMAP_ROBOT_AGENT_SLAM_SHARED_GRID_TILES_H_

#include <array>
#include <cstdint>
#include <memory>
#include <unordered_set>
#include <vector>

#include <Eigen/Core>

#include "shared/core/rigid2d.h"

namespace fleetmap {

struct SharedTileGridOptions {
  double resolution = 0.05;  // metres per cell
  float log_odds_hit = 0.85f;
  float log_odds_miss = -0.4f;
  float log_odds_min = -4.0f;
  float log_odds_max = 4.0f;
  // A cell that was hit counts as an obstacle (for matching and likelihoods) above this
  // log-odds: low, like GMapping's, because grazing beams clear wall cells they pass.
  float occupied_log_odds = -1.0f;
};

// One occupancy cell: log-odds plus the running mean of the beam end points that hit it, as an
// offset from the cell centre in 1/65536 of a cell. The mean is what lets particles match with
// sub-cell accuracy on a 5 cm grid.
struct TileCell {
  static constexpr int16_t kNoHit = INT16_MIN;
  float log_odds = 0.0f;
  int16_t hit_x = kNoHit;
  int16_t hit_y = kNoHit;
};

// A particle's occupancy map, stored as 64 x 64-cell tiles held by shared_ptr. Copies share
// every tile; a tile is cloned the first time a grid writes to a tile it does not own (copy on
// write). Ownership is an id the particle filter hands out, so that after resampling no two
// particles ever write to the same tile, and concurrent readers of shared tiles are safe.
class SharedTileGrid {
 public:
  static constexpr int kTileBits = 6;
  static constexpr int kTileSize = 1 << kTileBits;
  struct Tile {
    uint64_t owner = 0;
    std::array<TileCell, kTileSize * kTileSize> cells;
  };

  explicit SharedTileGrid(const SharedTileGridOptions& options = SharedTileGridOptions(),
                          uint64_t owner = 1);

  // The id whose tiles this grid may modify in place. Give every copy a fresh id.
  void set_owner(uint64_t owner) { owner_ = owner; }
  uint64_t owner() const { return owner_; }
  double resolution() const { return options_.resolution; }
  const SharedTileGridOptions& options() const { return options_; }

  // Integer cell of a point (floor).
  Eigen::Array2i CellOf(const Eigen::Vector2d& point) const;
  // The cell, or nullptr when its tile does not exist (never observed).
  const TileCell* Cell(int x, int y) const;

  // Ray-traces beams from `origin` (map frame): cells along each beam become freer, the end
  // cell more occupied when `hit[i]` is set.
  void InsertRays(const Eigen::Vector2d& origin, const std::vector<Eigen::Vector2d>& ends,
                  const std::vector<uint8_t>& hit);

  // The mean hit point of the occupied cell nearest to `point` within `radius` cells (Chebyshev
  // neighbourhood); false when there is none.
  bool NearestHit(const Eigen::Vector2d& point, int radius, Eigen::Vector2d* hit,
                  double* squared_distance) const;

  // Memory accounting: the tiles this grid holds, and their bytes.
  size_t tile_count() const;
  void CollectTiles(std::unordered_set<const Tile*>* tiles) const;
  static size_t TileBytes() { return sizeof(Tile); }

 private:
  TileCell* MutableCell(int x, int y);
  void GrowToTile(int tx, int ty);
  void UpdateFree(int x, int y);
  void UpdateHit(int x, int y, const Eigen::Vector2d& point);

  SharedTileGridOptions options_;
  uint64_t owner_;
  // Tiles cover [tile_x0_, tile_x0_ + tiles_w_) x [tile_y0_, tile_y0_ + tiles_h_), row-major.
  int tile_x0_ = 0;
  int tile_y0_ = 0;
  int tiles_w_ = 0;
  int tiles_h_ = 0;
  std::vector<std::shared_ptr<Tile>> tiles_;
};

}  // namespace fleetmap

#endif  // FLEETMAP_ROBOT_AGENT_SLAM_SHARED_GRID_TILES_H_
