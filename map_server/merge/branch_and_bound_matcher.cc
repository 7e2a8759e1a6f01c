#include "map_server/merge/branch_and_bound_matcher.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

struct Node {
  int rotation = 0;
  int x = 0;  // first cell offset of the block
  int y = 0;
  float score = 0.0f;
};

// The source points rotated by one lattice angle, as integer target cells at zero offset.
struct RotatedPoints {
  double angle = 0.0;
  std::vector<Eigen::Array2i> cells;
};

struct SearchContext {
  const ScoreGridPyramid* pyramid;
  const std::vector<RotatedPoints>* rotations;
  int window_x;
  int window_y;
  double resolution;
  Eigen::Vector2d center_translation;
  const std::vector<ExclusionZone>* exclusions;
};

float Score(const SearchContext& ctx, int level, const Node& node) {
  const RotatedPoints& r = (*ctx.rotations)[static_cast<size_t>(node.rotation)];
  float sum = 0.0f;
  for (const Eigen::Array2i& c : r.cells) sum += ctx.pyramid->Value(level, c.x() + node.x, c.y() + node.y);
  return r.cells.empty() ? 0.0f : sum / static_cast<float>(r.cells.size());
}

Rigid2d NodePose(const SearchContext& ctx, const Node& node) {
  const RotatedPoints& r = (*ctx.rotations)[static_cast<size_t>(node.rotation)];
  return Rigid2d(ctx.center_translation + ctx.resolution * Eigen::Vector2d(node.x, node.y), r.angle);
}

bool Excluded(const SearchContext& ctx, const Node& node) {
  if (ctx.exclusions->empty()) return false;
  const Rigid2d pose = NodePose(ctx, node);
  return std::any_of(
      ctx.exclusions->begin(), ctx.exclusions->end(), [&](const ExclusionZone& zone) {
        return (pose.translation() - zone.center.translation()).norm() < zone.linear &&
               std::abs(NormalizeAngle(pose.rotation() - zone.center.rotation())) < zone.angular;
      });
}

void SortDescending(std::vector<Node>* nodes) {
  std::sort(nodes->begin(), nodes->end(), [](const Node& a, const Node& b) { return a.score > b.score; });
}

// Depth-first branch and bound; `best` holds the best leaf found so far.
void Recurse(const SearchContext& ctx, std::vector<Node> candidates, int level, Node* best,
             float* best_score) {
  for (const Node& node : candidates) {
    if (node.score <= *best_score) break;
    if (level == 0) {
      if (Excluded(ctx, node)) continue;
      *best = node;
      *best_score = node.score;
      continue;
    }
    const int half = 1 << (level - 1);
    std::vector<Node> children;
    children.reserve(4);
    for (int dy : {0, half}) {
      for (int dx : {0, half}) {
        Node child{node.rotation, node.x + dx, node.y + dy, 0.0f};
        if (child.x > ctx.window_x || child.y > ctx.window_y) continue;
        child.score = Score(ctx, level - 1, child);
        children.push_back(child);
      }
    }
    SortDescending(&children);
    Recurse(ctx, std::move(children), level - 1, best, best_score);
  }
}

}  // namespace

BranchAndBoundMatcher::BranchAndBoundMatcher(const ScoreGrid& grid,
                                             const BranchAndBoundOptions& options)
    : grid_(grid), options_(options), pyramid_(grid, options.max_levels) {}

std::optional<MatchCandidate> BranchAndBoundMatcher::Search(
    const std::vector<Eigen::Vector2d>& source_points, const SearchWindow& window, double min_score,
    const std::vector<ExclusionZone>& exclusions) const {
  if (source_points.empty() || grid_.empty()) return std::nullopt;
  const double resolution = grid_.resolution();
  double max_radius = resolution;
  for (const Eigen::Vector2d& p : source_points) max_radius = std::max(max_radius, p.norm());
  // Step so that the farthest point moves by about one cell (Hess et al., eq. 7).
  double step = std::acos(std::max(-1.0, 1.0 - resolution * resolution / (2.0 * max_radius * max_radius)));
  step = std::min(step, options_.max_angular_step);
  const double half_angle = std::min(std::max(0.0, window.angular_half_extent), M_PI);
  int num = static_cast<int>(std::ceil(half_angle / step));
  int first = -num, last = num;
  if (half_angle >= M_PI - 1e-9) {
    step = M_PI / std::max(num, 1);  // the full circle in equal steps, no duplicate at +-pi
    last = num - 1;
  }

  std::vector<RotatedPoints> rotations;
  rotations.reserve(static_cast<size_t>(last - first + 1));
  for (int k = first; k <= last; ++k) {
    RotatedPoints r;
    r.angle = NormalizeAngle(window.center.rotation() + k * step);
    const Rigid2d pose(window.center.translation(), r.angle);
    r.cells.reserve(source_points.size());
    for (const Eigen::Vector2d& p : source_points) {
      const Eigen::Vector2d c = grid_.ToCellCoordinates(pose * p);
      r.cells.emplace_back(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
    }
    rotations.push_back(std::move(r));
  }

  SearchContext ctx;
  ctx.pyramid = &pyramid_;
  ctx.rotations = &rotations;
  ctx.window_x = static_cast<int>(std::ceil(window.linear_half_extent.x() / resolution));
  ctx.window_y = static_cast<int>(std::ceil(window.linear_half_extent.y() / resolution));
  ctx.resolution = resolution;
  ctx.center_translation = window.center.translation();
  ctx.exclusions = &exclusions;

  const int extent = 2 * std::max(ctx.window_x, ctx.window_y) + 1;
  int top = 0;
  while ((1 << top) < extent && top + 1 < pyramid_.levels()) ++top;
  const int block = 1 << top;
  std::vector<Node> candidates;
  for (int r = 0; r < static_cast<int>(rotations.size()); ++r) {
    for (int y = -ctx.window_y; y <= ctx.window_y; y += block) {
      for (int x = -ctx.window_x; x <= ctx.window_x; x += block) {
        Node node{r, x, y, 0.0f};
        node.score = Score(ctx, top, node);
        candidates.push_back(node);
      }
    }
  }
  SortDescending(&candidates);
  Node best;
  float best_score = static_cast<float>(min_score);
  bool found = false;
  {
    const float before = best_score;
    Recurse(ctx, std::move(candidates), top, &best, &best_score);
    found = best_score > before;
  }
  if (!found) return std::nullopt;
  return MatchCandidate{NodePose(ctx, best), best_score};
}

double BranchAndBoundMatcher::ScoreAt(const std::vector<Eigen::Vector2d>& source_points,
                                      const Rigid2d& pose) const {
  if (source_points.empty()) return 0.0;
  double sum = 0.0;
  for (const Eigen::Vector2d& p : source_points) {
    const Eigen::Vector2d c = grid_.ToCellCoordinates(pose * p);
    sum += grid_.Value(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
  }
  return sum / static_cast<double>(source_points.size());
}

double BranchAndBoundMatcher::OverlapAt(const std::vector<Eigen::Vector2d>& source_points,
                                        const Rigid2d& pose) const {
  if (source_points.empty()) return 0.0;
  int known = 0;
  for (const Eigen::Vector2d& p : source_points) {
    const Eigen::Vector2d c = grid_.ToCellCoordinates(pose * p);
    known += grid_.Known(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
  }
  return static_cast<double>(known) / static_cast<double>(source_points.size());
}

}  // namespace fleetmap
