#include "map_server/merge/pose_refiner.h"

#include <cmath>

#include <Eigen/Dense>

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
    result.inlier_fraction = static_cast<double>(inliers) / static_cast<double>(source_points.size());
  }
  result.mean_inlier_distance = inliers > 0 ? sum / inliers : 0.0;
  return result;
}

namespace {

// Sum of Huber costs, and the weighted normal equations when `h`/`g` are given.
double Cost(const LikelihoodField& field, const std::vector<Eigen::Vector2d>& points,
            const Rigid2d& pose, const PoseRefinerOptions& options, Eigen::Matrix3d* h,
            Eigen::Vector3d* g) {
  if (h) h->setZero();
  if (g) g->setZero();
  const Eigen::Matrix2d r = pose.rotation_matrix();
  const double cutoff = field.max_distance() * 0.999;
  double cost = 0.0;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = pose * p;
    Eigen::Vector2d grad;
    const double d = field.DistanceAndGradient(q, &grad);
    if (d >= cutoff) continue;  // unmatched: no information, no pull
    const double delta = options.huber_delta;
    const double w = d <= delta ? 1.0 : delta / d;
    cost += d <= delta ? 0.5 * d * d : delta * (d - 0.5 * delta);
    if (!h) continue;
    const Eigen::Vector2d dq_dtheta(-(r * p).y(), (r * p).x());
    const Eigen::Vector3d j(grad.x(), grad.y(), grad.dot(dq_dtheta));
    *h += w * j * j.transpose();
    *g += w * j * d;
  }
  return cost;
}

}  // namespace

RefinedPose RefinePose(const LikelihoodField& target_field,
                       const std::vector<Eigen::Vector2d>& source_points, const Rigid2d& initial,
                       const PoseRefinerOptions& options) {
  Rigid2d pose = initial;
  double lambda = 1e-3;
  bool converged = false;
  Eigen::Matrix3d h;
  Eigen::Vector3d g;
  double cost = Cost(target_field, source_points, pose, options, &h, &g);
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Matrix3d damped = h;
    damped.diagonal() += lambda * (h.diagonal().array() + 1e-9).matrix();
    const Eigen::Vector3d step = damped.ldlt().solve(-g);
    if (!step.allFinite()) break;
    const Rigid2d candidate(pose.translation() + step.head<2>(), pose.rotation() + step.z());
    const double new_cost = Cost(target_field, source_points, candidate, options, nullptr, nullptr);
    if (new_cost < cost) {
      pose = candidate;
      cost = Cost(target_field, source_points, pose, options, &h, &g);
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
  if ((pose.translation() - initial.translation()).norm() > options.max_translation_change ||
      std::abs(NormalizeAngle(pose.rotation() - initial.rotation())) > options.max_rotation_change) {
    pose = initial;
    converged = false;
  }
  RefinedPose result = EvaluatePose(target_field, source_points, pose, options.inlier_distance);
  result.converged = converged;
  return result;
}

}  // namespace fleetmap
