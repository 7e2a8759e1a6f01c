#include "robot_agent/sim/world_builder.h"

#include <algorithm>
#include <cmath>

namespace fleetmap::sim {

WorldBuilder::WorldBuilder(const std::string& name, double resolution,
                           const Eigen::Vector2d& size, double margin)
    : world_(resolution, Eigen::Vector2d(-margin, -margin),
             static_cast<int>(std::lround((size.x() + 2 * margin) / resolution)),
             static_cast<int>(std::lround((size.y() + 2 * margin) / resolution))) {
  world_.name = name;
  for (int y = 0; y < world_.height(); ++y) {
    for (int x = 0; x < world_.width(); ++x) world_.SetState(x, y, CellState::kUnknown);
  }
  SetBox(Eigen::Vector2d::Zero(), size, CellState::kOccupied);
}

void WorldBuilder::SetBox(const Eigen::Vector2d& min, const Eigen::Vector2d& max,
                          CellState state) {
  const double res = world_.resolution();
  // Cells whose centres lie inside the box; centres sit at half cells, never on a boundary
  // given in whole cells, so the box edges are exact.
  const int x0 = static_cast<int>(std::ceil((min.x() - world_.origin().x()) / res - 0.5));
  const int x1 = static_cast<int>(std::floor((max.x() - world_.origin().x()) / res - 0.5));
  const int y0 = static_cast<int>(std::ceil((min.y() - world_.origin().y()) / res - 0.5));
  const int y1 = static_cast<int>(std::floor((max.y() - world_.origin().y()) / res - 0.5));
  for (int y = std::max(0, y0); y <= std::min(world_.height() - 1, y1); ++y) {
    for (int x = std::max(0, x0); x <= std::min(world_.width() - 1, x1); ++x) {
      world_.SetState(x, y, state);
    }
  }
}

void WorldBuilder::Carve(const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
  SetBox(min, max, CellState::kFree);
}

void WorldBuilder::Fill(const Eigen::Vector2d& min, const Eigen::Vector2d& max) {
  SetBox(min, max, CellState::kOccupied);
}

void WorldBuilder::AddColouredBox(const std::string& label, const Eigen::Vector2d& min,
                                  const Eigen::Vector2d& max, double height, const Rgb& color) {
  Fill(min, max);
  const Eigen::Vector2d pad(0.06, 0.06);
  world_.patches.push_back(WallPatch{label, min - pad, max + pad, 0.0, height, color});
}

void WorldBuilder::AddPoster(const std::string& label, const Eigen::Vector2d& a,
                             const Eigen::Vector2d& b, double z_min, double z_max,
                             const Rgb& color) {
  // A thin footprint around the face: hits on the face land inside it, hits on the wall's other
  // face (kWall away) do not.
  const Eigen::Vector2d pad(0.06, 0.06);
  world_.patches.push_back(WallPatch{label, a.cwiseMin(b) - pad, a.cwiseMax(b) + pad, z_min,
                                     z_max, color});
}

void WorldBuilder::AddPlace(const std::string& name, double x, double y, double heading) {
  world_.places.push_back(Place{name, Eigen::Vector2d(x, y), heading});
}

void WorldBuilder::RoomsAlongX(double x0, int count, double pitch, double y0, double y1,
                               double door_y0, double door_y1, const std::string& name_prefix) {
  for (int i = 0; i < count; ++i) {
    const double left = x0 + i * pitch;
    const double right = left + pitch - kWall;
    Carve({left, y0}, {right, y1});
    const double centre = 0.5 * (left + right);
    Carve({centre - kDoor / 2, door_y0}, {centre + kDoor / 2, door_y1});
    if (!name_prefix.empty()) {
      AddPlace(name_prefix + std::to_string(i + 1), centre, 0.5 * (y0 + y1));
    }
  }
}

void WorldBuilder::RoomsAlongY(double y0, int count, double pitch, double x0, double x1,
                               double door_x0, double door_x1, const std::string& name_prefix) {
  for (int i = 0; i < count; ++i) {
    const double bottom = y0 + i * pitch;
    const double top = bottom + pitch - kWall;
    Carve({x0, bottom}, {x1, top});
    const double centre = 0.5 * (bottom + top);
    Carve({door_x0, centre - kDoor / 2}, {door_x1, centre + kDoor / 2});
    if (!name_prefix.empty()) {
      AddPlace(name_prefix + std::to_string(i + 1), 0.5 * (x0 + x1), centre);
    }
  }
}

}  // namespace fleetmap::sim
