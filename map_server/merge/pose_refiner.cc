#include "map_server/merge/pose_refiner.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace fleetmap {

RefinedPose EvaluatePose(const LikelihoodField& target_field,
                         const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& pose,
                         double inlier_distance) {
  RefinedPose result;
  result.pose = pose;
  int inliers = 0;
  double sum = 0.0;
  for (const Eigen::Vector2d& p : source_points) {
    const double d = target_field.Distance(pose * p);
    if (d < inlier_distance) {
      ++inliers;
      sum += d;
    }
  }
  if (!source_points.empty()) {
    result.inlier_fraction =
        static_cast<double>(inliers) / static_cast<double>(source_points.size());
  }
  result.mean_inlier_distance = inliers > 0 ? sum / inliers : 0.0;
  return result;
}

namespace {

// The sided distances of the source points; each point's sector is chosen once, at the start
// (the refinement turns by hundredths of a radian).
struct SidedLookup {
  const SidedDistanceField& field;
  const std::vector<Eigen::Vector2d>& points;
  std::vector<int> sectors;
  double max_distance() const { return field.max_distance(); }
  double operator()(size_t i, const Rigid2d& pose, Eigen::Vector2d* grad) const {
    return field.DistanceAndGradient(pose * points[i], sectors[i], grad);
  }
};

std::vector<int> Sectors(const std::vector<Eigen::Vector2d>& normals, const Rigid2d& pose) {
  const Eigen::Matrix2d r = pose.rotation_matrix();
  std::vector<int> sectors;
  sectors.reserve(normals.size());
  for (const Eigen::Vector2d& n : normals) sectors.push_back(SidedDistanceField::SectorOf(r * n));
  return sectors;
}

// Sum of Huber costs over the points near a wall, and the weighted normal equations when
// `h`/`g` are given.
double Cost(const SidedLookup& lookup, const Rigid2d& pose, const PoseRefinerOptions& options,
            Eigen::Matrix3d* h, Eigen::Vector3d* g) {
  if (h) h->setZero();
  if (g) g->setZero();
  const Eigen::Matrix2d r = pose.rotation_matrix();
  const double cutoff = lookup.max_distance() * 0.999;
  const double delta = options.huber_delta;
  const auto huber = [delta](double x) {
    return x <= delta ? 0.5 * x * x : delta * (x - 0.5 * delta);
  };
  double cost = 0.0;
  for (size_t i = 0; i < lookup.points.size(); ++i) {
    const Eigen::Vector2d& p = lookup.points[i];
    Eigen::Vector2d grad;
    const double d = lookup(i, pose, &grad);
    if (d >= cutoff) continue;  // unmatched: no information, no pull
    if (options.max_pull_distance > 0.0 && d >= options.max_pull_distance) {
      // Counted at the limit, so that moving a point past it is not a way to lower the cost.
      cost += huber(options.max_pull_distance);
      continue;
    }
    const double w = d <= delta ? 1.0 : delta / d;
    cost += huber(d);
    if (!h) continue;
    const Eigen::Vector2d dq_dtheta(-(r * p).y(), (r * p).x());
    const Eigen::Vector3d j(grad.x(), grad.y(), grad.dot(dq_dtheta));
    *h += w * j * j.transpose();
    *g += w * j * d;
  }
  return cost;
}

// Levenberg-Marquardt from `initial`; the final pose, and whether it converged.
Rigid2d Minimise(const SidedLookup& lookup, const Rigid2d& initial,
                 const PoseRefinerOptions& options, bool* converged_out) {
  Rigid2d pose = initial;
  double lambda = 1e-3;
  bool converged = false;
  Eigen::Matrix3d h;
  Eigen::Vector3d g;
  double cost = Cost(lookup, pose, options, &h, &g);
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Matrix3d damped = h;
    damped.diagonal() += lambda * (h.diagonal().array() + 1e-9).matrix();
    const Eigen::Vector3d step = damped.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const Rigid2d candidate(pose.translation() + step.head<2>(), pose.rotation() + step.z());
    const double new_cost = Cost(lookup, candidate, options, nullptr, nullptr);
    if (new_cost < cost) {
      pose = candidate;
      cost = Cost(lookup, pose, options, &h, &g);
      lambda = std::max(lambda * 0.3, 1e-6);
      if (step.head<2>().norm() < 1e-5 && std::abs(step.z()) < 1e-6) {
        converged = true;
        break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e6) {
        converged = true;  // no downhill step left
        break;
      }
    }
  }
  *converged_out = converged;
  return pose;
}

// Whether the refinement slid too far from where it started.
bool Slid(const Rigid2d& pose, const Rigid2d& start, const PoseRefinerOptions& options) {
  return (pose.translation() - start.translation()).norm() > options.max_translation_change ||
         std::abs(NormalizeAngle(pose.rotation() - start.rotation())) > options.max_rotation_change;
}

// The best pose of the lattice center +- steps * step, rotations +- turns * angular_step, by the
// sum of exp(-d^2 / 2 sigma^2) over the sided distances of the points, times a weak prior
// towards `prior` (where the points leave a direction free, as along a plain corridor, the
// search must not wander to the end of its lattice).
Rigid2d BestOnLattice(const SidedDistanceField& field, const SidedPoints& source,
                      const Rigid2d& center, double step, int steps, double angular_step, int turns,
                      double sigma, const Rigid2d& prior, double prior_sigma,
                      const Box2d& allowed) {
  const double inverse_two_sigma2 = 0.5 / (sigma * sigma);
  Rigid2d best = center;
  double best_score = -1.0;
  std::vector<Eigen::Vector2d> rotated(source.points.size());
  Eigen::Vector2d unused;
  for (int a = -turns; a <= turns; ++a) {
    const double angle = center.rotation() + a * angular_step;
    const Rigid2d turn(Eigen::Vector2d::Zero(), angle);
    for (size_t i = 0; i < source.points.size(); ++i) rotated[i] = turn * source.points[i];
    const std::vector<int> sectors = Sectors(source.normals, turn);
    for (int iy = -steps; iy <= steps; ++iy) {
      for (int ix = -steps; ix <= steps; ++ix) {
        const Eigen::Vector2d t = center.translation() + step * Eigen::Vector2d(ix, iy);
        if ((t.array() < allowed.min.array()).any() || (t.array() > allowed.max.array()).any()) {
          continue;
        }
        double score = 0.0;
        for (size_t i = 0; i < rotated.size(); ++i) {
          const double d = field.DistanceAndGradient(rotated[i] + t, sectors[i], &unused);
          score += std::exp(-d * d * inverse_two_sigma2);
        }
        const double offset = (t - prior.translation()).norm() / prior_sigma;
        score *= std::exp(-0.5 * offset * offset);
        if (score > best_score) {
          best_score = score;
          best = Rigid2d(t, angle);
        }
      }
    }
  }
  return best;
}

// The neighbourhood of a lattice answer searched again on sided distances: two cells and
// 0.01 rad steps, then one cell and 0.005 rad around the best.
Rigid2d SidedSearch(const SidedDistanceField& field, const SidedPoints& source,
                    const Rigid2d& center, const Box2d& allowed,
                    const PoseRefinerOptions& options) {
  if (source.points.empty()) return center;
  const double step = 2.0 * field.resolution(), angular_step = 0.01;
  const Rigid2d coarse = BestOnLattice(
      field, source, center, step,
      static_cast<int>(std::ceil(options.sided_search_translation / step)), angular_step,
      static_cast<int>(std::ceil(options.sided_search_rotation / angular_step)),
      options.sided_search_sigma, center, options.sided_search_prior, allowed);
  return BestOnLattice(field, source, coarse, 0.5 * step, 1, 0.5 * angular_step, 1,
                       options.sided_search_sigma, center, options.sided_search_prior, allowed);
}

}  // namespace

RefinedPose RefineSidedPose(const SidedDistanceField& target_field, const SidedPoints& coarse,
                            const SidedPoints& fine, const Rigid2d& initial, const Box2d& allowed,
                            const PoseRefinerOptions& options) {
  const Rigid2d start = SidedSearch(target_field, coarse, initial, allowed, options);
  bool converged = false;
  Rigid2d pose = Minimise(SidedLookup{target_field, fine.points, Sectors(fine.normals, start)},
                          start, options, &converged);
  if (Slid(pose, start, options)) {
    pose = start;
    converged = false;
  }
  RefinedPose result;
  result.pose = pose;
  result.converged = converged;
  return result;
}

}  // namespace fleetmap
