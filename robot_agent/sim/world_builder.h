#ifndef FLEETMAP_ROBOT_AGENT_SIM_WORLD_BUILDER_H_
#define FLEETMAP_ROBOT_AGENT_SIM_WORLD_BUILDER_H_

#include <string>

#include <Eigen/Core>

#include "robot_agent/sim/world.h"

namespace fleetmap::sim {

// Builds worlds from code by carving free space out of a solid building outline, so that the
// shipped worlds are reproducible and their dimensions are exact (boxes given in metres on the
// cell grid). The building occupies [0, size]; a border of unknown cells surrounds it.
class WorldBuilder {
 public:
  WorldBuilder(const std::string& name, double resolution, const Eigen::Vector2d& size,
               double margin = 1.0);

  // Marks the cells whose centres lie in [min, max] free (rooms, corridors, doors).
  void Carve(const Eigen::Vector2d& min, const Eigen::Vector2d& max);
  // Marks them occupied (furniture, pillars, solid blocks).
  void Fill(const Eigen::Vector2d& min, const Eigen::Vector2d& max);
  // A box of furniture with a painted side (e.g. a green cabinet): occupied + a colour patch.
  void AddColouredBox(const std::string& label, const Eigen::Vector2d& min,
                      const Eigen::Vector2d& max, double height, const Rgb& color);
  // A poster on a wall face running from a to b (both on the face), between heights z_min and
  // z_max.
  void AddPoster(const std::string& label, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                 double z_min, double z_max, const Rgb& color);
  void AddPlace(const std::string& name, double x, double y, double heading = 0.0);

  // A row of rooms along x: room i spans x in [x0 + i * pitch, x0 + (i + 1) * pitch - wall]
  // and y in [y0, y1]; each gets a 1 m door centred in it through the wall band [door_y0, door_y1].
  // With a non-empty `name_prefix`, room i's centre becomes the place `<prefix><i + 1>`.
  void RoomsAlongX(double x0, int count, double pitch, double y0, double y1, double door_y0,
                   double door_y1, const std::string& name_prefix = "");
  // The same along y (doors through the band [door_x0, door_x1]).
  void RoomsAlongY(double y0, int count, double pitch, double x0, double x1, double door_x0,
                   double door_x1, const std::string& name_prefix = "");

  const World& world() const { return world_; }
  World Build() const { return world_; }

  static constexpr double kWall = 0.2;  // wall thickness, metres
  static constexpr double kDoor = 1.0;  // door width, metres

 private:
  void SetBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max, CellState state);
  World world_;
};

}  // namespace fleetmap::sim

#endif  // FLEETMAP_ROBOT_AGENT_SIM_WORLD_BUILDER_H_
