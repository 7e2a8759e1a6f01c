#include "shared/matching/pose_refinement.h"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "shared/matching/match_grid_pyramid.h"

namespace fleetmap {
namespace {

struct Linearization {
  double cost = 0.0;
  Eigen::Matrix3d scan_information = Eigen::Matrix3d::Zero();  // positive semi-definite
  Eigen::Vector3d scan_gradient = Eigen::Vector3d::Zero();
  double score = 0.0;
  double inlier_fraction = 0.0;
};

// Keeps the curvature of one point's squared distance positive semi-definite: between two
// walls the field has ridges whose negative curvature would make the step meaningless.
Eigen::Matrix2d ClampToPositive(const Eigen::Matrix2d& m) {
  const double a = m(0, 0), b = m(0, 1), c = m(1, 1);
  const double mean = 0.5 * (a + c);
  const double radius = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  if (mean - radius >= 0.0) return m;
  if (mean + radius <= 0.0) return Eigen::Matrix2d::Zero();
  // Keep the positive eigenvalue's rank-one part.
  const double lambda = mean + radius;
  Eigen::Vector2d v = std::abs(b) > 1e-12 ? Eigen::Vector2d(b, lambda - a)
                                          : (a >= c ? Eigen::Vector2d(1.0, 0.0) : Eigen::Vector2d(0.0, 1.0));
  v.normalize();
  return lambda * v * v.transpose();
}

// Per point the cost is (c^2 / 2 sigma^2) log(1 + f / c^2), f the interpolated squared distance
// (a Cauchy loss on the distance). Its Newton step uses the field's own curvature: near a wall
// f = (n . dq)^2, so this equals Gauss-Newton on point-to-line distances.
Linearization Linearize(const std::vector<Eigen::Vector2f>& points, const MatchGrid& grid,
                        const Rigid2d& pose, const PoseRefinementOptions& options) {
  Linearization lin;
  const double half_inv_var = 0.5 / (options.point_sigma * options.point_sigma);
  const double c2 = options.robust_scale * options.robust_scale;
  const double inlier2 = options.inlier_distance * options.inlier_distance;
  const Eigen::Matrix2d rotation = pose.rotation_matrix();
  const float max_squared = static_cast<float>(grid.max_squared_distance());
  int inliers = 0;
  double score = 0.0;
  for (const Eigen::Vector2f& p : points) {
    const Eigen::Vector2d rotated = rotation * p.cast<double>();
    Eigen::Vector2d gradient;
    Eigen::Matrix2d curvature;
    const double f = std::max(0.0, grid.SquaredDistance(rotated + pose.translation(), &gradient, &curvature));
    score += SquaredDistanceScore(static_cast<float>(f), max_squared);
    if (f < inlier2) ++inliers;
    lin.cost += c2 * half_inv_var * std::log1p(f / c2);
    const double w = half_inv_var / (1.0 + f / c2);
    // dq/dxi = [I | perp], perp = d(R p)/dtheta.
    const Eigen::Vector2d perp(-rotated.y(), rotated.x());
    const Eigen::Matrix2d h = ClampToPositive(curvature);
    const Eigen::Vector2d h_perp = h * perp;
    Eigen::Matrix3d info;
    info.topLeftCorner<2, 2>() = h;
    info.topRightCorner<2, 1>() = h_perp;
    info.bottomLeftCorner<1, 2>() = h_perp.transpose();
    info(2, 2) = perp.dot(h_perp);
    lin.scan_information.noalias() += w * info;
    lin.scan_gradient.noalias() += w * Eigen::Vector3d(gradient.x(), gradient.y(), gradient.dot(perp));
  }
  const double n = static_cast<double>(points.size());
  lin.score = score / n;
  lin.inlier_fraction = inliers / n;
  return lin;
}

Eigen::Vector3d PriorWeights(const PoseRefinementOptions& options) {
  auto weight = [](double sigma) { return sigma > 0.0 ? 1.0 / (sigma * sigma) : 0.0; };
  const double wt = weight(options.prior_translation_sigma);
  return Eigen::Vector3d(wt, wt, weight(options.prior_rotation_sigma));
}

Eigen::Vector3d PriorResidual(const Rigid2d& pose, const Rigid2d& prior) {
  return Eigen::Vector3d(pose.x() - prior.x(), pose.y() - prior.y(),
                         NormalizeAngle(pose.rotation() - prior.rotation()));
}

double TotalCost(const Linearization& lin, const Rigid2d& pose, const Rigid2d& prior,
                 const Eigen::Vector3d& prior_weights) {
  const Eigen::Vector3d e = PriorResidual(pose, prior);
  return lin.cost + 0.5 * e.dot(prior_weights.cwiseProduct(e));
}

PoseRefinement RefineOnce(const std::vector<Eigen::Vector2f>& points, const MatchGrid& grid,
                          const Rigid2d& initial, const Rigid2d& prior,
                          const PoseRefinementOptions& options) {
  PoseRefinement result;
  result.pose = initial;
  if (points.empty() || !initial.IsFinite() || !prior.IsFinite() || !(options.point_sigma > 0.0) ||
      !(options.robust_scale > 0.0)) {
    result.covariance = Eigen::Matrix3d::Identity() * 1e6;
    return result;
  }
  const Eigen::Vector3d prior_weights = PriorWeights(options);
  Rigid2d pose = initial;
  Linearization lin = Linearize(points, grid, pose, options);
  double cost = TotalCost(lin, pose, prior, prior_weights);
  double lambda = 1e-3;
  int iteration = 0;
  for (; iteration < options.max_iterations; ++iteration) {
    const Eigen::Matrix3d h = lin.scan_information + Eigen::Matrix3d(prior_weights.asDiagonal());
    const Eigen::Vector3d g =
        lin.scan_gradient + prior_weights.cwiseProduct(PriorResidual(pose, prior));
    Eigen::Matrix3d damped = h;
    damped.diagonal() += lambda * (h.diagonal().array() + 1e-9).matrix();
    const Eigen::Vector3d delta = damped.ldlt().solve(-g);
    if (!delta.allFinite()) break;
    const Rigid2d candidate(pose.translation() + delta.head<2>(), pose.rotation() + delta.z());
    const Linearization candidate_lin = Linearize(points, grid, candidate, options);
    const double candidate_cost = TotalCost(candidate_lin, candidate, prior, prior_weights);
    if (candidate_cost <= cost) {
      pose = candidate;
      lin = candidate_lin;
      cost = candidate_cost;
      lambda = std::max(1e-6, lambda * 0.1);
      if (delta.head<2>().norm() < 1e-5 && std::abs(delta.z()) < 1e-5) {
        result.converged = true;
        ++iteration;
        break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e6) {
        result.converged = true;  // no descent direction left: a minimum at this resolution
        break;
      }
    }
  }
  result.pose = pose;
  result.iterations = iteration;
  result.scan_information = lin.scan_information;
  result.score = lin.score;
  result.inlier_fraction = lin.inlier_fraction;
  const Eigen::Matrix3d h = lin.scan_information + Eigen::Matrix3d(prior_weights.asDiagonal());
  // A tiny ridge keeps the inverse finite when neither scan nor prior constrains a direction.
  result.covariance = (h + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
  return result;
}

}  // namespace

PoseRefinement RefinePose(const std::vector<Eigen::Vector2f>& points, const MatchGrid& grid,
                          const Rigid2d& initial, const Rigid2d& prior,
                          const PoseRefinementOptions& options) {
  PoseRefinement result = RefineOnce(points, grid, initial, prior, options);
  if (!(options.fine_robust_scale > 0.0) || !(options.fine_robust_scale < options.robust_scale) ||
      points.empty()) {
    return result;
  }
  PoseRefinementOptions fine = options;
  fine.robust_scale = options.fine_robust_scale;
  PoseRefinement refined = RefineOnce(points, grid, result.pose, prior, fine);
  refined.iterations += result.iterations;
  return refined;
}

}  // namespace fleetmap
