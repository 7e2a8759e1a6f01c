#include "map_server/merge/branch_and_bound_matcher.h"

#include <algorithm>
#include <cmath>

namespace fleetmap {
namespace {

Rigid2d NodePose(const SearchLattice& lattice, const LatticeNode& node) {
  const LatticeRotation& r = lattice.rotations[static_cast<size_t>(node.rotation)];
  return Rigid2d(lattice.center_translation + lattice.resolution * Eigen::Vector2d(node.x, node.y),
                 r.angle);
}

bool Excluded(const SearchLattice& lattice, const std::vector<ExclusionZone>& exclusions,
              const LatticeNode& node) {
  if (exclusions.empty()) return false;
  const Rigid2d pose = NodePose(lattice, node);
  return std::any_of(exclusions.begin(), exclusions.end(),
                     [&](const ExclusionZone& zone) { return zone.Contains(pose); });
}

// The four blocks one level down, those inside the window.
std::vector<LatticeNode> Children(const SearchLattice& lattice, const LatticeNode& node) {
  const int half = 1 << (node.level - 1);
  std::vector<LatticeNode> children;
  children.reserve(4);
  for (int dy : {0, half}) {
    for (int dx : {0, half}) {
      const LatticeNode child{node.level - 1, node.rotation, node.x + dx, node.y + dy, 0.0f};
      if (child.x > lattice.window_x || child.y > lattice.window_y) continue;
      children.push_back(child);
    }
  }
  return children;
}

void SortDescending(std::vector<LatticeNode>* nodes) {
  std::sort(nodes->begin(), nodes->end(),
            [](const LatticeNode& a, const LatticeNode& b) { return a.score > b.score; });
}

}  // namespace

BranchAndBoundMatcher::BranchAndBoundMatcher(const ScoreGrid& grid,
                                             const BranchAndBoundOptions& options)
    : grid_(grid), options_(options), pyramid_(grid, options.max_levels) {}

SearchLattice BranchAndBoundMatcher::MakeLattice(const std::vector<Eigen::Vector2d>& source_points,
                                                 const SearchWindow& window) const {
  SearchLattice lattice;
  if (source_points.empty() || grid_.empty()) return lattice;
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

  lattice.rotations.reserve(static_cast<size_t>(last - first + 1));
  for (int k = first; k <= last; ++k) {
    LatticeRotation r;
    r.angle = NormalizeAngle(window.center.rotation() + k * step);
    const Rigid2d pose(window.center.translation(), r.angle);
    r.cells.reserve(source_points.size());
    for (const Eigen::Vector2d& p : source_points) {
      const Eigen::Vector2d c = grid_.ToCellCoordinates(pose * p);
      r.cells.emplace_back(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
    }
    lattice.rotations.push_back(std::move(r));
  }
  lattice.window_x = static_cast<int>(std::ceil(window.linear_half_extent.x() / resolution));
  lattice.window_y = static_cast<int>(std::ceil(window.linear_half_extent.y() / resolution));
  lattice.resolution = resolution;
  lattice.center_translation = window.center.translation();
  const int extent = 2 * std::max(lattice.window_x, lattice.window_y) + 1;
  while ((1 << lattice.top) < extent && lattice.top + 1 < pyramid_.levels()) ++lattice.top;
  return lattice;
}

float BranchAndBoundMatcher::Bound(const SearchLattice& lattice, const LatticeNode& node) const {
  const LatticeRotation& r = lattice.rotations[static_cast<size_t>(node.rotation)];
  float sum = 0.0f;
  for (const Eigen::Array2i& c : r.cells)
    sum += pyramid_.Value(node.level, c.x() + node.x, c.y() + node.y);
  return r.cells.empty() ? 0.0f : sum / static_cast<float>(r.cells.size());
}

std::vector<LatticeNode> BranchAndBoundMatcher::TopNodes(const SearchLattice& lattice) const {
  const int block = 1 << lattice.top;
  std::vector<LatticeNode> nodes;
  for (int r = 0; r < static_cast<int>(lattice.rotations.size()); ++r) {
    for (int y = -lattice.window_y; y <= lattice.window_y; y += block) {
      for (int x = -lattice.window_x; x <= lattice.window_x; x += block) {
        LatticeNode node{lattice.top, r, x, y, 0.0f};
        node.score = Bound(lattice, node);
        nodes.push_back(node);
      }
    }
  }
  return nodes;
}

std::optional<MatchCandidate> BranchAndBoundMatcher::Search(
    const std::vector<Eigen::Vector2d>& source_points, const SearchWindow& window, double min_score,
    const std::vector<ExclusionZone>& exclusions) const {
  const SearchLattice lattice = MakeLattice(source_points, window);
  if (lattice.rotations.empty()) return std::nullopt;
  // Depth first, best child first; `best` holds the best leaf found so far.
  LatticeNode best;
  float best_score = static_cast<float>(min_score);
  bool found = false;
  const auto recurse = [&](const auto& self, std::vector<LatticeNode> candidates) -> void {
    for (const LatticeNode& node : candidates) {
      if (node.score <= best_score) break;
      if (node.level == 0) {
        if (Excluded(lattice, exclusions, node)) continue;
        best = node;
        best_score = node.score;
        found = true;
        continue;
      }
      std::vector<LatticeNode> children = Children(lattice, node);
      for (LatticeNode& child : children) child.score = Bound(lattice, child);
      SortDescending(&children);
      self(self, std::move(children));
    }
  };
  std::vector<LatticeNode> top = TopNodes(lattice);
  SortDescending(&top);
  recurse(recurse, std::move(top));
  if (!found) return std::nullopt;
  return MatchCandidate{NodePose(lattice, best), best_score};
}

PeakSearch BranchAndBoundMatcher::Peaks(const std::vector<Eigen::Vector2d>& source_points,
                                        const SearchWindow& window, double min_score,
                                        const std::vector<ExclusionZone>& exclusions) const {
  return PeakSearch(*this, MakeLattice(source_points, window), static_cast<float>(min_score),
                    exclusions);
}

PeakSearch::PeakSearch(const BranchAndBoundMatcher& matcher, SearchLattice lattice, float min_score,
                       std::vector<ExclusionZone> exclusions)
    : matcher_(matcher),
      lattice_(std::move(lattice)),
      min_score_(min_score),
      exclusions_(std::move(exclusions)) {
  if (lattice_.rotations.empty()) return;
  for (const LatticeNode& node : matcher_.TopNodes(lattice_)) {
    if (node.score > min_score_) frontier_.push(node);
  }
}

std::optional<MatchCandidate> PeakSearch::Next() {
  // Best first: the first leaf off the frontier scores at least every bound left on it, so it
  // is the best pose left.
  while (!frontier_.empty()) {
    const LatticeNode node = frontier_.top();
    frontier_.pop();
    if (node.level == 0) {
      if (Excluded(lattice_, exclusions_, node)) continue;
      return MatchCandidate{NodePose(lattice_, node), node.score};
    }
    for (LatticeNode child : Children(lattice_, node)) {
      child.score = matcher_.Bound(lattice_, child);
      if (child.score > min_score_) frontier_.push(child);
    }
  }
  return std::nullopt;
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
