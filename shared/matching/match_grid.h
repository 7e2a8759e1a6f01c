#ifndef FLEETMAP_SHARED_MATCHING_MATCH_GRID_H_
#define FLEETMAP_SHARED_MATCHING_MATCH_GRID_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "shared/core/likelihood_field.h"
#include "shared/core/occupancy_grid.h"
#include "shared/core/rigid2d.h"
#include "shared/matching/scan_segments.h"
#include "shared/matching/surface_elements.h"

namespace fleetmap {

// Per-point score of a squared distance: 1 on an obstacle, falling to 0 at max_distance
// (1 - d^2 / max^2, an Epanechnikov kernel).
inline float SquaredDistanceScore(float squared_distance, float max_squared_distance) {
  return squared_distance >= max_squared_distance ? 0.0f
                                                  : 1.0f - squared_distance / max_squared_distance;
}

struct MatchGridOptions {
  double resolution = 0.05;  // metres per cell
  // Distances are clamped here; it is also how far around each obstacle point the grid is
  // updated, so it bounds the cost of adding a point and the basin of the refinement.
  double max_distance = 0.3;
  // Points added in one batch are fitted to the walls they lie on (see FitSurfaceElements), and
  // the field holds the distance to those short wall pieces rather than to the sampled points.
  SurfaceFitOptions surface;
  // Batches added with AddPoints are scans in beam order: consecutive returns on one surface
  // but far apart are also joined by segments (see JoinConsecutiveReturns).
  bool join_scan_returns = true;
  ScanSegmentOptions scan_segments;
  // Remember which cells the scans have seen (the rays from each batch's origin to its points,
  // and the points' cells). A point in a cell no scan has seen then scores unknown_score instead
  // of 0: the target cannot say whether a wall is there. Without it, a scan seen from the other
  // side of a box or round a corner matches best where its unseen parts land on seen walls.
  bool track_observed = false;
  float unknown_score = 0.4f;
  // Seen space is tracked in square blocks of this many cells a side (1: per cell), aligned to
  // the grid's 64-cell growth blocks: a finer distance field can keep the seen-space rules of a
  // coarser one (SeenFree's 3 x 3 neighbourhood is then 3 x 3 blocks). Must divide 64.
  int observed_block = 1;
};

// A batch of points ready to go into any grid with the same options: in the map frame, fitted to
// the walls they lie on. Prepared once, it goes into several grids at the cost of stamping only
// (a rolling local map puts every scan into two).
struct MatchGridBatch {
  std::vector<Eigen::Vector2d> points;
  bool has_origin = false;  // the batch is a scan seen from `origin` (its rays are known)
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> free_ends;  // beams that saw nothing up to there
  std::vector<SurfaceElement> elements;    // the wall pieces and joined returns to stamp
};

// The target a scan is matched against: for every cell centre, the squared distance (m^2,
// clamped at max_distance^2) to the nearest obstacle: a short piece of wall where the points of
// a batch lie on a line, the point itself elsewhere. Squared, because near a wall it is a
// quadratic that bicubic interpolation reproduces exactly, so the interpolated field has its
// minimum exactly on the wall and a well-defined curvature there (a distance cone has neither). Unlike the core LikelihoodField it can grow
// incrementally: adding a point only touches the cells within max_distance of it, which is what
// makes a rolling local map affordable at every scan. Distances are exact to the points and wall
// pieces added (not to cell centres), so sub-cell wall positions survive.
class MatchGrid {
 public:
  explicit MatchGrid(const MatchGridOptions& options = MatchGridOptions());
  // Copies an existing distance field (its distances are clamped at `max_distance`).
  static MatchGrid FromLikelihoodField(const LikelihoodField& field, double max_distance);
  // Obstacles are the centres of cells more likely occupied than `occupied_probability`.
  static MatchGrid FromOccupancyGrid(const OccupancyGrid& grid, float occupied_probability,
                                     const MatchGridOptions& options);
  static MatchGrid FromPoints(const std::vector<Eigen::Vector2d>& points,
                              const MatchGridOptions& options);

  double resolution() const { return options_.resolution; }
  double max_distance() const { return options_.max_distance; }
  const Eigen::Vector2d& origin() const { return origin_; }  // lower-left corner of cell (0, 0)
  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return obstacle_count_ == 0; }
  int64_t obstacle_count() const { return obstacle_count_; }

  // Adds one obstacle point (map frame), as a point. The first point or wall piece whose centre
  // falls in a cell represents it; later ones in the same cell are ignored, so re-observing a
  // wall costs almost nothing.
  void AddPoint(const Eigen::Vector2d& point);
  // Adds a scan's `points_in_frame` (in beam order, seen from the frame's origin) transformed by
  // `frame_in_map`, fitted to the walls they lie on; grows the grid once for all of them.
  void AddPoints(const std::vector<Eigen::Vector2f>& points_in_frame, const Rigid2d& frame_in_map);
  // The same, and with track_observed the rays to `free_ends_in_frame` (beams that saw nothing up
  // to there) mark space as seen without adding obstacles.
  void AddPoints(const std::vector<Eigen::Vector2f>& points_in_frame,
                 const std::vector<Eigen::Vector2f>& free_ends_in_frame, const Rigid2d& frame_in_map);
  // AddPoints in two steps, for one scan going into several grids with these options.
  MatchGridBatch PrepareScan(const std::vector<Eigen::Vector2f>& points_in_frame,
                             const std::vector<Eigen::Vector2f>& free_ends_in_frame,
                             const Rigid2d& frame_in_map) const;
  void Add(const MatchGridBatch& batch);

  double max_squared_distance() const { return options_.max_distance * options_.max_distance; }
  // Squared distance at a cell centre; max_distance^2 outside the grid.
  float CellSquaredDistance(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return max_squared_;
    return squared_[static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x)];
  }
  // Bicubic (Catmull-Rom) interpolation of the squared distance, with its gradient and Hessian
  // (either may be null). Outside the grid: max_distance^2 and zero derivatives.
  double SquaredDistance(const Eigen::Vector2d& point, Eigen::Vector2d* gradient = nullptr,
                         Eigen::Matrix2d* hessian = nullptr) const;
  // Interpolated distance (metres).
  double Distance(const Eigen::Vector2d& point) const;

  // Whether any scan saw the cell; always true when observed cells are not tracked.
  bool CellObserved(int x, int y) const {
    if (!options_.track_observed) return true;
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    return observed_[static_cast<size_t>(y >> observed_shift_) *
                         static_cast<size_t>(width_ >> observed_shift_) +
                     static_cast<size_t>(x >> observed_shift_)] != 0;
  }
  // Whether any scan saw the cell holding `point` (true when not tracked).
  bool Observed(const Eigen::Vector2d& point) const;
  // Whether `point` lies inside space the scans saw free: its cell and all 8 around it were
  // crossed by rays, and no obstacle in the grid is within `clearance` (metres). A cell next to
  // any surface never qualifies (the cells behind a wall or inside a pillar are never crossed),
  // however closely rays have passed it. Always false when observed cells are not tracked.
  bool SeenFree(const Eigen::Vector2d& point, double clearance) const;
  // Per-cell score for correlative search, 0..1: 1 - d^2 / max^2 near obstacles, at least
  // unknown_score in cells no scan saw (see MatchGridOptions::track_observed).
  float CellScore(int x, int y) const;

  // Row-major squared distances, index = y * width + x.
  const std::vector<float>& squared_distances() const { return squared_; }

 private:
  void GrowToInclude(const Eigen::Vector2d& min, const Eigen::Vector2d& max);
  // Fits the points (map frame) to their walls; with an origin, also joins consecutive returns.
  MatchGridBatch Prepare(std::vector<Eigen::Vector2d> points, const Eigen::Vector2d* origin,
                         std::vector<Eigen::Vector2d> free_ends = {}) const;
  void MarkRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to);
  void Stamp(const SurfaceElement& element);

  MatchGridOptions options_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  int width_ = 0;
  int height_ = 0;
  int64_t obstacle_count_ = 0;
  float max_squared_ = 0.0f;
  std::vector<float> squared_;
  std::vector<uint8_t> has_point_;  // 1 where a cell already holds an obstacle point
  // 1 where a scan saw the block of observed_block x observed_block cells (track_observed only;
  // blocks divide the 64-cell growth blocks, so the grid holds whole blocks, and are powers of 2).
  std::vector<uint8_t> observed_;
  int observed_shift_ = 0;  // log2(observed_block)
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_MATCHING_MATCH_GRID_H_
