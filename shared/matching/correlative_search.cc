#include "shared/matching/correlative_search.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

// Rotated-and-translated points of one candidate angle, as base cell indices.
struct DiscreteScan {
  double angle_offset = 0.0;
  std::vector<Eigen::Array2i> cells;
};

double AngularStep(const std::vector<Eigen::Vector2f>& points, double resolution,
                   const CorrelativeSearchOptions& options) {
  if (options.angular_step > 0.0) return options.angular_step;
  double max_range = 0.0;
  for (const Eigen::Vector2f& p : points) max_range = std::max(max_range, static_cast<double>(p.norm()));
  max_range = std::max(max_range, 3.0 * resolution);
  // The angle that moves the farthest point by one cell.
  return std::acos(std::max(-1.0, 1.0 - resolution * resolution / (2.0 * max_range * max_range)));
}

std::vector<DiscreteScan> DiscretizeScans(const std::vector<Eigen::Vector2f>& points,
                                          const Rigid2d& guess, const Eigen::Vector2d& origin,
                                          double resolution, double step, int angle_steps) {
  std::vector<DiscreteScan> scans;
  scans.reserve(static_cast<size_t>(2 * angle_steps + 1));
  for (int a = -angle_steps; a <= angle_steps; ++a) {
    DiscreteScan scan;
    scan.angle_offset = a * step;
    const Rigid2d pose(guess.translation(), guess.rotation() + scan.angle_offset);
    scan.cells.reserve(points.size());
    for (const Eigen::Vector2f& p : points) {
      const Eigen::Vector2d q = (pose * Eigen::Vector2d(p.cast<double>()) - origin) / resolution;
      // Points absurdly far off the grid are dropped rather than overflowing an int.
      if (!(std::abs(q.x()) < 1e8 && std::abs(q.y()) < 1e8)) continue;
      scan.cells.emplace_back(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())));
    }
    scans.push_back(std::move(scan));
  }
  return scans;
}

bool ValidInput(const std::vector<Eigen::Vector2f>& points, const Rigid2d& guess,
                const CorrelativeSearchOptions& options) {
  return !points.empty() && guess.IsFinite() && options.linear_window >= 0.0 &&
         options.angular_window >= 0.0 && std::isfinite(options.linear_window) &&
         std::isfinite(options.angular_window) && options.angular_window < 4.0 &&
         options.linear_window < 1e4;
}

}  // namespace

std::optional<CorrelativeMatch> SearchBruteForce(const std::vector<Eigen::Vector2f>& points,
                                                 const MatchGrid& grid, const Rigid2d& guess,
                                                 const CorrelativeSearchOptions& options) {
  if (!ValidInput(points, guess, options) || grid.empty()) return std::nullopt;
  const double res = grid.resolution();
  const double step = AngularStep(points, res, options);
  const int angle_steps = static_cast<int>(std::ceil(options.angular_window / step));
  const int window = static_cast<int>(std::ceil(options.linear_window / res));
  const std::vector<DiscreteScan> scans =
      DiscretizeScans(points, guess, grid.origin(), res, step, angle_steps);
  const double n = static_cast<double>(points.size());
  std::optional<CorrelativeMatch> best;
  double best_penalised = -1.0;
  for (const DiscreteScan& scan : scans) {
    const double angle_penalty = options.rotation_penalty * scan.angle_offset * scan.angle_offset;
    for (int dy = -window; dy <= window; ++dy) {
      for (int dx = -window; dx <= window; ++dx) {
        double sum = 0.0;
        for (const Eigen::Array2i& c : scan.cells) {
          sum += grid.CellScore(c.x() + dx, c.y() + dy);
        }
        const double score = sum / n;
        const double lin2 = (dx * dx + dy * dy) * res * res;
        const double penalised =
            score * std::exp(-(options.translation_penalty * lin2 + angle_penalty));
        if (penalised > best_penalised) {
          best_penalised = penalised;
          best = CorrelativeMatch{
              Rigid2d(guess.translation() + res * Eigen::Vector2d(dx, dy),
                      guess.rotation() + scan.angle_offset),
              score};
        }
      }
    }
  }
  if (!best || best->score < options.min_score) return std::nullopt;
  return best;
}

namespace {

struct Candidate {
  int scan_index;
  int x;  // translation offset of the block's first cell, in base cells
  int y;
  int score;  // sum of quantised scores (upper bound above level 0)
};

int ScoreCandidate(const MatchGridPyramid& pyramid, int level, const DiscreteScan& scan, int x,
                   int y) {
  int sum = 0;
  for (const Eigen::Array2i& c : scan.cells) sum += pyramid.BlockScore(level, c.x() + x, c.y() + y);
  return sum;
}

// Depth-first, best child first; prunes every block whose bound cannot beat `best`.
void Branch(const MatchGridPyramid& pyramid, const std::vector<DiscreteScan>& scans,
            std::vector<Candidate>& candidates, int level, int window, Candidate* best) {
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  for (const Candidate& candidate : candidates) {
    if (candidate.score <= best->score) break;
    if (level == 0) {
      *best = candidate;
      continue;
    }
    const int half = 1 << (level - 1);
    std::vector<Candidate> children;
    children.reserve(4);
    for (int oy : {0, half}) {
      for (int ox : {0, half}) {
        const int x = candidate.x + ox, y = candidate.y + oy;
        if (x > window || y > window) continue;
        const DiscreteScan& scan = scans[static_cast<size_t>(candidate.scan_index)];
        children.push_back({candidate.scan_index, x, y, ScoreCandidate(pyramid, level - 1, scan, x, y)});
      }
    }
    Branch(pyramid, scans, children, level - 1, window, best);
  }
}

}  // namespace

std::optional<CorrelativeMatch> SearchBranchAndBound(const std::vector<Eigen::Vector2f>& points,
                                                     const MatchGridPyramid& pyramid,
                                                     const Rigid2d& guess,
                                                     const CorrelativeSearchOptions& options) {
  if (!ValidInput(points, guess, options) || pyramid.base_width() == 0) return std::nullopt;
  const double res = pyramid.resolution();
  const double step = AngularStep(points, res, options);
  const int angle_steps = static_cast<int>(std::ceil(options.angular_window / step));
  const int window = static_cast<int>(std::ceil(options.linear_window / res));
  const std::vector<DiscreteScan> scans =
      DiscretizeScans(points, guess, pyramid.origin(), res, step, angle_steps);
  const int top = pyramid.levels() - 1;
  const int block = 1 << top;
  std::vector<Candidate> candidates;
  for (int s = 0; s < static_cast<int>(scans.size()); ++s) {
    for (int y = -window; y <= window; y += block) {
      for (int x = -window; x <= window; x += block) {
        candidates.push_back({s, x, y, ScoreCandidate(pyramid, top, scans[static_cast<size_t>(s)], x, y)});
      }
    }
  }
  const double n = static_cast<double>(points.size());
  Candidate best{-1, 0, 0, static_cast<int>(std::ceil(options.min_score * 255.0 * n)) - 1};
  Branch(pyramid, scans, candidates, top, window, &best);
  if (best.scan_index < 0) return std::nullopt;
  const DiscreteScan& scan = scans[static_cast<size_t>(best.scan_index)];
  return CorrelativeMatch{Rigid2d(guess.translation() + res * Eigen::Vector2d(best.x, best.y),
                                  guess.rotation() + scan.angle_offset),
                          best.score / (255.0 * n)};
}

}  // namespace fleetmap
