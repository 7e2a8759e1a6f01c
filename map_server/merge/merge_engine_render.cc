// MergeEngine: the global map and the quality figures.

#include <cmath>

#include "map_server/merge/internal/merge_engine_state.h"
#include "map_server/merge/merge_engine.h"

namespace fleetmap {

std::optional<OccupancyGrid> MergeEngine::RenderGlobalMap(const std::optional<Box2d>& box, double resolution,
                                                         std::string* error) const {
  if (!std::isfinite(resolution) || resolution <= 0.0) {
    if (error) *error = "resolution must be a positive number of metres";
    return std::nullopt;
  }
  OccupancyGridOptions grid_options = options_.render_grid;
  grid_options.resolution = resolution;
  const std::vector<std::string> placed = PlacedRobots();
  std::optional<Box2d> extent = box;
  if (!extent) {
    for (const std::string& robot : placed) {
      const LogOddsCanvas& canvas = robots_.at(robot)->canvas;
      if (canvas.empty()) continue;
      const Box2d e = canvas.Extent();
      if (!extent) {
        extent = e;
      } else {
        extent->min = extent->min.cwiseMin(e.min);
        extent->max = extent->max.cwiseMax(e.max);
      }
    }
    if (!extent) return OccupancyGrid(grid_options);
  }
  if (!extent->min.allFinite() || !extent->max.allFinite() || (extent->max.array() <= extent->min.array()).any()) {
    if (error) *error = "the box must have finite corners with max > min";
    return std::nullopt;
  }
  const Eigen::Vector2d cells = (extent->max - extent->min) / resolution;
  if (cells.x() * cells.y() > static_cast<double>(options_.max_render_cells)) {
    if (error) *error = "the requested map is too large (" + std::to_string(cells.x() * cells.y()) + " cells)";
    return std::nullopt;
  }
  if (std::abs(resolution - options_.render_resolution) < 1e-9) {
    // The incrementally kept canvases, summed over the placed robots.
    LogOddsCanvas sum(resolution);
    for (const std::string& robot : placed) sum.AddCanvas(robots_.at(robot)->canvas, extent);
    return sum.ToGrid(grid_options, extent);
  }
  LogOddsCanvas canvas(resolution);
  for (const std::string& robot : placed) {
    const RobotState& state = *robots_.at(robot);
    for (const auto& [id, submap] : state.submaps) {
      const auto pose = graph_.NodePose({robot, id});
      const auto bounds = pose ? state.SubmapBounds(id, *pose) : std::nullopt;
      if (!bounds || (bounds->max.array() < extent->min.array()).any() ||
          (bounds->min.array() > extent->max.array()).any()) {
        continue;
      }
      canvas.AddSubmap(submap.grid, *pose, 1.0f);
    }
  }
  return canvas.ToGrid(grid_options, extent);
}

MergeQuality MergeEngine::Quality(const std::optional<Box2d>& region) const {
  MergeQuality quality;
  double sum_t2 = 0.0, sum_r2 = 0.0;
  for (const EdgeResidual& r : graph_.Residuals()) {
    std::string a, b;
    if (r.detection) {
      a = graph_.detections()[r.index].observer.robot;
      b = graph_.detections()[r.index].observed.robot;
    } else {
      const RelativeEdge& e = graph_.edges()[r.index];
      if (e.kind == EdgeKind::kOdometry || e.kind == EdgeKind::kLoopClosure) continue;
      a = e.from.robot;
      b = e.to.robot;
    }
    if (a == b || !IsPlaced(a) || !IsPlaced(b)) continue;
    ++quality.inter_robot_edges;
    sum_t2 += r.translation * r.translation;
    sum_r2 += r.rotation * r.rotation;
    quality.inter_robot_max_translation = std::max(quality.inter_robot_max_translation, r.translation);
  }
  if (quality.inter_robot_edges > 0) {
    quality.inter_robot_rms_translation = std::sqrt(sum_t2 / quality.inter_robot_edges);
    quality.inter_robot_rms_rotation = std::sqrt(sum_r2 / quality.inter_robot_edges);
  }
  // Consistency: every pair of placed robots, cell by cell on the shared canvas lattice.
  const std::vector<std::string> placed = PlacedRobots();
  const float wall = options_.match.grid.occupied_log_odds;
  const float free = options_.match.grid.free_log_odds;
  for (size_t i = 0; i < placed.size(); ++i) {
    const LogOddsCanvas& a = robots_.at(placed[i])->canvas;
    if (a.empty()) continue;
    Box2d box = a.Extent();
    if (region) {
      box.min = box.min.cwiseMax(region->min);
      box.max = box.max.cwiseMin(region->max);
    }
    const double res = a.resolution();
    const Eigen::Array2i lo((box.min / res).array().floor().cast<int>());
    const Eigen::Array2i hi((box.max / res).array().ceil().cast<int>());
    for (size_t k = i + 1; k < placed.size(); ++k) {
      const LogOddsCanvas& b = robots_.at(placed[k])->canvas;
      for (int y = lo.y(); y < hi.y(); ++y) {
        for (int x = lo.x(); x < hi.x(); ++x) {
          const float va = a.Sum(x, y), vb = b.Sum(x, y);
          const bool a_known = va > wall || va < free, b_known = vb > wall || vb < free;
          if (!a_known || !b_known) continue;
          ++quality.overlapping_cells;
          if ((va > wall) != (vb > wall)) ++quality.disagreeing_cells;
        }
      }
    }
  }
  return quality;
}

}  // namespace fleetmap
