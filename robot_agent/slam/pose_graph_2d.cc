#include "robot_agent/slam/pose_graph_2d.h"

#include <array>

#include <ceres/ceres.h>

#include "shared/core/relative_pose_residual.h"

namespace fleetmap {
namespace {

// Whitened error of the measured relative pose against the one the two poses imply.
struct RelativePoseCost {
  explicit RelativePoseCost(const PoseGraphConstraint& c) : constraint(c) {}

  template <typename T>
  bool operator()(const T* from, const T* to, T* residual) const {
    RelativePoseResidual(from, to, constraint.relative, constraint.translation_sigma,
                         constraint.rotation_sigma, residual);
    return true;
  }

  PoseGraphConstraint constraint;
};

}  // namespace

PoseGraphSummary OptimizePoseGraph(const std::vector<PoseGraphConstraint>& constraints,
                                   const std::vector<bool>& fixed, const PoseGraphOptions& options,
                                   std::vector<Rigid2d>* poses) {
  PoseGraphSummary summary;
  const int n = static_cast<int>(poses->size());
  if (n == 0) {
    summary.message = "empty graph";
    return summary;
  }
  std::vector<std::array<double, 3>> values(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Rigid2d& p = (*poses)[static_cast<size_t>(i)];
    values[static_cast<size_t>(i)] = {p.x(), p.y(), p.rotation()};
  }
  ceres::Problem problem;
  for (const PoseGraphConstraint& c : constraints) {
    if (c.from < 0 || c.to < 0 || c.from >= n || c.to >= n || c.from == c.to) continue;
    ceres::LossFunction* loss = c.robust_scale > 0.0 ? new ceres::HuberLoss(c.robust_scale) : nullptr;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<RelativePoseCost, 3, 3, 3>(new RelativePoseCost(c)),
                             loss, values[static_cast<size_t>(c.from)].data(),
                             values[static_cast<size_t>(c.to)].data());
  }
  for (int i = 0; i < n; ++i) {
    double* block = values[static_cast<size_t>(i)].data();
    if (!problem.HasParameterBlock(block)) continue;
    const bool is_fixed = fixed.empty() ? i == 0 : fixed[static_cast<size_t>(i)];
    if (is_fixed) problem.SetParameterBlockConstant(block);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary result;
  ceres::Solve(solver, &problem, &result);
  summary.ok = result.IsSolutionUsable();
  summary.iterations = static_cast<int>(result.iterations.size());
  summary.initial_cost = result.initial_cost;
  summary.final_cost = result.final_cost;
  summary.message = result.message;
  if (!summary.ok) return summary;
  for (int i = 0; i < n; ++i) {
    const std::array<double, 3>& v = values[static_cast<size_t>(i)];
    (*poses)[static_cast<size_t>(i)] = Rigid2d(v[0], v[1], v[2]);
  }
  return summary;
}

}  // namespace fleetmap
