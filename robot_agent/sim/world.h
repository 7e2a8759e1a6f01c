#ifndef FLEETMAP_ROBOT_AGENT_SIM_WORLD_H_
#define FLEETMAP_ROBOT_AGENT_SIM_WORLD_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace fleetmap::sim {

struct Rgb {
  uint8_t r = 0;
  uint8_t g = 0;
  uint8_t b = 0;
};

// A named spot (room, lab, corridor end) that scenarios can use as a waypoint or start.
struct Place {
  std::string name;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  double heading = 0.0;  // radians, used when a robot starts at the place
};

// A coloured patch on wall faces (a poster, a painted cabinet). PGM maps have no colour, so these
// live in the world's sidecar YAML. Wall hits whose point lies inside the footprint [min, max]
// show `color` between heights z_min and z_max.
struct WallPatch {
  std::string label;
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
  double z_min = 0.0;
  double z_max = 0.0;
  Rgb color;
};

enum class CellState : uint8_t { kFree = 0, kOccupied = 1, kUnknown = 2 };

// Where a ray first entered a blocked cell.
struct RayHit {
  bool hit = false;
  double distance = 0.0;          // metres from the ray origin; max_range when !hit
  Eigen::Vector2d point = Eigen::Vector2d::Zero();
  bool x_face = false;            // the hit face is perpendicular to x (a wall running along y)
};

// The simulated world: a 2D grid of free/occupied/unknown cells (occupied and unknown block
// robots and rays alike) plus the metadata a PGM cannot hold: places, coloured patches, wall
// height. Cell (0, 0) has its lower-left corner at origin(); y grows up.
class World {
 public:
  World() = default;
  // A world of free cells.
  World(double resolution, const Eigen::Vector2d& origin, int width, int height);

  double resolution() const { return resolution_; }
  const Eigen::Vector2d& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }

  bool Contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  CellState State(int x, int y) const {
    return Contains(x, y) ? static_cast<CellState>(cells_[Index(x, y)]) : CellState::kUnknown;
  }
  void SetState(int x, int y, CellState state) {
    if (Contains(x, y)) cells_[Index(x, y)] = static_cast<uint8_t>(state);
  }
  // Outside the grid counts as blocked.
  bool IsBlocked(int x, int y) const { return State(x, y) != CellState::kFree; }
  bool IsBlockedAt(const Eigen::Vector2d& point) const;
  Eigen::Vector2i CellAt(const Eigen::Vector2d& point) const;
  Eigen::Vector2d CellCenter(int x, int y) const;

  // Walks the grid from `from` along `angle` (Amanatides-Woo DDA) to the first blocked cell, up
  // to max_range. A ray starting inside a blocked cell hits at distance 0.
  RayHit CastRay(const Eigen::Vector2d& from, double angle, double max_range) const;
  // True when the segment a -> b crosses no blocked cell.
  bool LineOfSight(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const;

  // The patch covering a wall hit point, if any (later patches win).
  const WallPatch* PatchAt(const Eigen::Vector2d& point) const;
  std::optional<Place> FindPlace(const std::string& name) const;

  std::string name;
  double wall_height = 2.5;  // metres
  std::vector<Place> places;
  std::vector<WallPatch> patches;

 private:
  size_t Index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
  }

  double resolution_ = 0.05;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  std::vector<uint8_t> cells_;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_WORLD_H_
