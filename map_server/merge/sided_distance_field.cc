#include "map_server/merge/sided_distance_field.h"

#include <cmath>

#include "map_server/merge/grid_points.h"

namespace fleetmap {

int SidedDistanceField::SectorOf(const Eigen::Vector2d& normal) {
  if (normal.isZero()) return -1;
  const int k =
      static_cast<int>(std::lround(std::atan2(normal.y(), normal.x()) / (2.0 * M_PI / kSectors)));
  return (k % kSectors + kSectors) % kSectors;
}

SidedDistanceField::SidedDistanceField(const OccupancyGrid& target, const Box2d& box,
                                       float occupied_log_odds, float free_log_odds,
                                       std::shared_ptr<const LikelihoodField> unsided)
    : unsided_(std::move(unsided)) {
  const CellIndex lo = target.CellAt(box.min).max(CellIndex(0, 0));
  const CellIndex hi =
      target.CellAt(box.max).min(CellIndex(target.width() - 1, target.height() - 1));
  const CellIndex size = (hi - lo + 1).max(CellIndex(0, 0));
  const Eigen::Vector2d origin = target.origin() + target.resolution() * lo.cast<double>().matrix();
  std::array<OccupancyGrid, kSectors> sectors;
  for (OccupancyGrid& sector : sectors) {
    sector = OccupancyGrid(target.options(), origin, size.x(), size.y());
  }
  const double min_cosine = std::cos(kMaxAngle);
  for (int y = lo.y(); y <= hi.y(); ++y) {
    for (int x = lo.x(); x <= hi.x(); ++x) {
      const CellIndex cell(x, y);
      if (target.LogOdds(cell) <= occupied_log_odds) continue;
      const Eigen::Vector2d normal = WallNormalAt(target, cell, free_log_odds);
      for (int k = 0; k < kSectors; ++k) {
        const double angle = 2.0 * M_PI * k / kSectors;
        if (normal.isZero() ||
            normal.dot(Eigen::Vector2d(std::cos(angle), std::sin(angle))) >= min_cosine) {
          sectors[static_cast<size_t>(k)].SetLogOdds(cell - lo, 1.0f);
        }
      }
    }
  }
  LikelihoodFieldOptions options;
  options.occupied_probability = 0.5f;  // the sector grids hold 1 on their walls, 0 elsewhere
  options.max_distance = unsided_->max_distance();
  for (int k = 0; k < kSectors; ++k) {
    sectors_[static_cast<size_t>(k)] =
        std::make_unique<LikelihoodField>(sectors[static_cast<size_t>(k)], options);
  }
}

}  // namespace fleetmap
