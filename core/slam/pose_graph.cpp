#include "core/slam/pose_graph.hpp"

#include <array>
#include <cmath>
#include <memory>

#include <ceres/ceres.h>

namespace orthosonar::slam {

void relative_pose_residual(const double* a, const double* b, const SE2& z,
                            const Eigen::Vector3d& sigma, double* residuals, double* J_a,
                            double* J_b) {
  const Eigen::Vector3d inv_sigma_ = sigma.cwiseInverse();
  const SE2& z_ = z;
  const double ca = std::cos(a[2]), sa = std::sin(a[2]);
  const double cz = std::cos(z_.theta), sz = std::sin(z_.theta);
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  // q = R(a)^T (t_b - t_a) - t_z
  const double qx = ca * dx + sa * dy - z_.x;
  const double qy = -sa * dx + ca * dy - z_.y;
  // r_xy = R(z)^T q
  residuals[0] = inv_sigma_[0] * (cz * qx + sz * qy);
  residuals[1] = inv_sigma_[1] * (-sz * qx + cz * qy);
  residuals[2] = inv_sigma_[2] * wrap_angle(b[2] - a[2] - z_.theta);
  // M = R(z)^T R(a)^T, the derivative of r_xy with respect to t_b (and -M for t_a).
  const double m00 = cz * ca - sz * sa, m01 = cz * sa + sz * ca;
  const double m10 = -sz * ca - cz * sa, m11 = -sz * sa + cz * ca;
  // d q / d theta_a = dR(a)^T/dθ (t_b - t_a) = (-sa dx + ca dy, -ca dx - sa dy)
  const double dqx = -sa * dx + ca * dy, dqy = -ca * dx - sa * dy;
  if (J_a != nullptr) {
    double* J = J_a;  // row-major 3x3
    J[0] = -inv_sigma_[0] * m00;
    J[1] = -inv_sigma_[0] * m01;
    J[2] = inv_sigma_[0] * (cz * dqx + sz * dqy);
    J[3] = -inv_sigma_[1] * m10;
    J[4] = -inv_sigma_[1] * m11;
    J[5] = inv_sigma_[1] * (-sz * dqx + cz * dqy);
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = -inv_sigma_[2];
  }
  if (J_b != nullptr) {
    double* J = J_b;
    J[0] = inv_sigma_[0] * m00;
    J[1] = inv_sigma_[0] * m01;
    J[2] = 0.0;
    J[3] = inv_sigma_[1] * m10;
    J[4] = inv_sigma_[1] * m11;
    J[5] = 0.0;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = inv_sigma_[2];
  }
}

void pose_prior_residual(const double* x, const SE2& prior, const Eigen::Vector3d& sigma,
                         double* residuals, double* J_x) {
  const Eigen::Vector3d inv_sigma_ = sigma.cwiseInverse();
  const double c = std::cos(prior.theta), s = std::sin(prior.theta);
  const double dx = x[0] - prior.x, dy = x[1] - prior.y;
  residuals[0] = inv_sigma_[0] * (c * dx + s * dy);
  residuals[1] = inv_sigma_[1] * (-s * dx + c * dy);
  residuals[2] = inv_sigma_[2] * wrap_angle(x[2] - prior.theta);
  if (J_x != nullptr) {
    double* J = J_x;
    J[0] = inv_sigma_[0] * c;
    J[1] = inv_sigma_[0] * s;
    J[2] = 0.0;
    J[3] = -inv_sigma_[1] * s;
    J[4] = inv_sigma_[1] * c;
    J[5] = 0.0;
    J[6] = 0.0;
    J[7] = 0.0;
    J[8] = inv_sigma_[2];
  }
}

namespace {

// The Ceres cost functions: thin wrappers over the residuals above.
class RelativePoseCost final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  RelativePoseCost(const SE2& z, const Eigen::Vector3d& sigma, const Eigen::Matrix3d& mix)
      : z_(z), sigma_(sigma), mix_(mix), mixed_(!mix.isIdentity(0.0)) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    relative_pose_residual(p[0], p[1], z_, sigma_, r, J ? J[0] : nullptr, J ? J[1] : nullptr);
    if (mixed_) {
      using Row3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
      Eigen::Map<Eigen::Vector3d> rv(r);
      rv = (mix_ * rv).eval();
      for (int k = 0; k < 2 && J != nullptr; ++k) {
        if (J[k] == nullptr) continue;
        Eigen::Map<Row3> Jk(J[k]);
        Jk = (mix_ * Jk).eval();
      }
    }
    return true;
  }

 private:
  SE2 z_;
  Eigen::Vector3d sigma_;
  Eigen::Matrix3d mix_;
  bool mixed_;
};

class PosePriorCost final : public ceres::SizedCostFunction<3, 3> {
 public:
  PosePriorCost(const SE2& prior, const Eigen::Vector3d& sigma) : p_(prior), sigma_(sigma) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    pose_prior_residual(p[0], p_, sigma_, r, J ? J[0] : nullptr);
    return true;
  }

 private:
  SE2 p_;
  Eigen::Vector3d sigma_;
};

}  // namespace

namespace {

// Every option set explicitly, single-threaded: results are bit-reproducible. The sparse
// Cholesky is Eigen's (simplicial LDLT, AMD ordering): on a 1000-keyframe graph it
// factorises in a third of the time CHOLMOD's supernodal path takes, whose BLAS calls on
// blocks this small are mostly OpenMP thread wake-ups (docs/BENCHMARKS.md).
ceres::Solver::Options solver_options(const PoseGraphConfig& config) {
  ceres::Solver::Options opt;
  opt.minimizer_type = ceres::TRUST_REGION;
  opt.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  opt.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  opt.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  opt.num_threads = 1;
  opt.max_num_iterations = config.max_iterations;
  opt.function_tolerance = config.function_tolerance;
  opt.gradient_tolerance = config.gradient_tolerance;
  opt.parameter_tolerance = config.parameter_tolerance;
  opt.use_nonmonotonic_steps = false;
  opt.jacobi_scaling = true;
  opt.minimizer_progress_to_stdout = false;
  opt.logging_type = ceres::SILENT;
  opt.update_state_every_iteration = false;
  return opt;
}

ceres::Problem::Options problem_options() {
  ceres::Problem::Options popt;
  popt.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  popt.enable_fast_removal = false;
  return popt;
}

PoseGraphSummary summarise(const ceres::Solver::Summary& summary) {
  PoseGraphSummary out;
  out.usable = summary.IsSolutionUsable();
  out.iterations = static_cast<int>(summary.iterations.size());
  out.initial_cost = summary.initial_cost;
  out.final_cost = summary.final_cost;
  return out;
}

}  // namespace

PoseGraphSummary solve_pose_graph(std::vector<SE2>& poses, const SE2& prior,
                                  const Eigen::Vector3d& prior_sigma,
                                  const std::vector<GraphEdge>& edges,
                                  const PoseGraphConfig& config) {
  PoseGraphSummary out;
  if (poses.empty()) return out;
  std::vector<std::array<double, 3>> x(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) x[i] = {poses[i].x, poses[i].y, poses[i].theta};

  ceres::Problem problem(problem_options());
  for (auto& p : x) problem.AddParameterBlock(p.data(), 3);
  problem.AddResidualBlock(new PosePriorCost(prior, prior_sigma), nullptr, x[0].data());
  for (const GraphEdge& e : edges) {
    problem.AddResidualBlock(new RelativePoseCost(e.T_from_to, e.sigma, e.mix), nullptr,
                             x[static_cast<size_t>(e.from)].data(), x[static_cast<size_t>(e.to)].data());
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options(config), &problem, &summary);
  out = summarise(summary);
  if (out.usable) {
    for (size_t i = 0; i < poses.size(); ++i) {
      poses[i] = {x[i][0], x[i][1], wrap_angle(x[i][2])};
    }
  }
  return out;
}

PoseGraphSummary solve_leaf_pose(std::vector<SE2>& poses, int leaf,
                                 const std::vector<GraphEdge>& edges,
                                 const PoseGraphConfig& config) {
  PoseGraphSummary out;
  if (leaf < 0 || static_cast<size_t>(leaf) >= poses.size()) return out;
  // Only the leaf and the poses its edges reach; those are held constant.
  std::vector<std::array<double, 3>> x(poses.size());
  ceres::Problem problem(problem_options());
  const auto block = [&](int i) {
    auto& p = x[static_cast<size_t>(i)];
    if (!problem.HasParameterBlock(p.data())) {
      const SE2& T = poses[static_cast<size_t>(i)];
      p = {T.x, T.y, T.theta};
      problem.AddParameterBlock(p.data(), 3);
      if (i != leaf) problem.SetParameterBlockConstant(p.data());
    }
    return p.data();
  };
  block(leaf);
  for (const GraphEdge& e : edges) {
    if (e.from != leaf && e.to != leaf) continue;
    problem.AddResidualBlock(new RelativePoseCost(e.T_from_to, e.sigma, e.mix), nullptr,
                             block(e.from), block(e.to));
  }
  if (problem.NumResidualBlocks() == 0) return out;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options(config), &problem, &summary);
  out = summarise(summary);
  if (out.usable) {
    const auto& p = x[static_cast<size_t>(leaf)];
    poses[static_cast<size_t>(leaf)] = {p[0], p[1], wrap_angle(p[2])};
  }
  return out;
}

}  // namespace orthosonar::slam
