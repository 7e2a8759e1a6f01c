#include "map_server/server/global_map_renderer.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {

void FuseSubmap(const OccupancyGrid& submap_grid, const Rigid2d& submap_in_global, float weight,
                OccupancyGrid* canvas) {
  CellIndex known_min, known_max;
  if (!submap_grid.KnownBounds(&known_min, &known_max)) return;
  const double r = submap_grid.resolution();
  const Eigen::Vector2d lo = submap_grid.origin() + r * known_min.cast<double>().matrix();
  const Eigen::Vector2d hi = submap_grid.origin() + r * (known_max + 1).cast<double>().matrix();
  // The global box around the submap's observed part.
  Eigen::Vector2d box_min = Eigen::Vector2d::Constant(INFINITY);
  Eigen::Vector2d box_max = Eigen::Vector2d::Constant(-INFINITY);
  for (const Eigen::Vector2d& corner :
       {lo, hi, Eigen::Vector2d(lo.x(), hi.y()), Eigen::Vector2d(hi.x(), lo.y())}) {
    const Eigen::Vector2d g = submap_in_global * corner;
    box_min = box_min.cwiseMin(g);
    box_max = box_max.cwiseMax(g);
  }
  canvas->GrowToInclude(box_min, box_max);
  const CellIndex c0 = canvas->CellAt(box_min).max(CellIndex(0, 0));
  const CellIndex c1 = canvas->CellAt(box_max).min(CellIndex(canvas->width() - 1,
                                                             canvas->height() - 1));
  // Walk canvas cells; map each centre into the submap frame incrementally.
  const Rigid2d global_to_submap = submap_in_global.inverse();
  const Eigen::Matrix2d rotation = global_to_submap.rotation_matrix();
  const double cr = canvas->resolution();
  const Eigen::Vector2d step_x = rotation.col(0) * cr / r;
  const std::vector<float>& source = submap_grid.log_odds();
  const int sw = submap_grid.width();
  const int sh = submap_grid.height();
  for (int y = c0.y(); y <= c1.y(); ++y) {
    const Eigen::Vector2d row_start = global_to_submap * canvas->CellCenter(CellIndex(c0.x(), y));
    Eigen::Vector2d p = (row_start - submap_grid.origin()) / r;  // in source cell units
    for (int x = c0.x(); x <= c1.x(); ++x, p += step_x) {
      const int sx = static_cast<int>(std::floor(p.x()));
      const int sy = static_cast<int>(std::floor(p.y()));
      if (sx < 0 || sy < 0 || sx >= sw || sy >= sh) continue;
      const float v = source[static_cast<size_t>(sy) * sw + sx];
      if (v == 0.0f) continue;
      const CellIndex cell(x, y);
      float sum = canvas->LogOdds(cell) + weight * v;
      // Removing a contribution can leave float dust; that cell is unknown again.
      if (std::abs(sum) < 1e-4f) sum = 0.0f;
      canvas->SetLogOdds(cell, sum);
    }
  }
}

}  // namespace fleetmap
