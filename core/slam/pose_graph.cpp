#include "core/slam/pose_graph.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include <ceres/ceres.h>

#include "core/slam/pose_graph_pcg.hpp"

namespace orthosonar::slam {

void relative_pose_residual(const double* a, const double* b, const SE2& z,
                            const Eigen::Vector3d& sigma, double* residuals, double* J_a,
                            double* J_b) {
  relative_pose_residual(a, b, z, {std::cos(a[2]), std::sin(a[2]), std::cos(z.theta), std::sin(z.theta)}, sigma,
                         residuals, J_a, J_b);
}

void relative_pose_residual(const double* a, const double* b, const SE2& z, const HeadingTrig& trig,
                            const Eigen::Vector3d& sigma, double* residuals, double* J_a, double* J_b) {
  const Eigen::Vector3d inv_sigma_ = sigma.cwiseInverse();
  const SE2& z_ = z;
  const double ca = trig.cos_a, sa = trig.sin_a;
  const double cz = trig.cos_z, sz = trig.sin_z;
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

SE2 drift_corrected(const GraphEdge& e, double rate_rad_s) {
  SE2 z = e.T_from_to;
  if (e.dt_s != 0.0) z.theta -= rate_rad_s * e.dt_s;
  return z;
}

void drifting_pose_residual(const double* a, const double* b, const GraphEdge& e, double rate_rad_s,
                            double* residual, double* J_a, double* J_b, double* J_rate) {
  const SE2 z = drift_corrected(e, rate_rad_s);
  relative_pose_residual(a, b, z, e.sigma, residual, J_a, J_b);
  if (J_rate != nullptr) {
    // z.theta = theta - rate dt: the yaw residual moves by +dt / sigma_theta, and the xy
    // residual R(z)^T q rotates: d/d(z.theta) of (r0 / s0, r1 / s1) is (r1 / s1, -r0 / s0).
    const double dt = e.dt_s;
    J_rate[0] = -dt * (residual[1] * e.sigma[1]) / e.sigma[0];
    J_rate[1] = dt * (residual[0] * e.sigma[0]) / e.sigma[1];
    J_rate[2] = dt / e.sigma[2];
  }
}

namespace {

// The Ceres cost functions: thin wrappers over the residuals above.

// Applies an edge's residual mixing (GraphEdge::mix) to the residual and to the Jacobian
// blocks Ceres asked for: block k is 3 x cols[k], row-major.
template <int N>
void apply_mix(const Eigen::Matrix3d& mix, double* r, double** J, const std::array<int, N>& cols) {
  Eigen::Map<Eigen::Vector3d> rv(r);
  rv = (mix * rv).eval();
  for (int k = 0; k < N && J != nullptr; ++k) {
    if (J[k] == nullptr) continue;
    Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> Jk(J[k], 3, cols[static_cast<size_t>(k)]);
    Jk = (mix * Jk).eval();
  }
}

class RelativePoseCost final : public ceres::SizedCostFunction<3, 3, 3> {
 public:
  RelativePoseCost(const SE2& z, const Eigen::Vector3d& sigma, const Eigen::Matrix3d& mix)
      : z_(z), sigma_(sigma), mix_(mix), mixed_(!mix.isIdentity(0.0)) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    relative_pose_residual(p[0], p[1], z_, sigma_, r, J ? J[0] : nullptr, J ? J[1] : nullptr);
    if (mixed_) apply_mix<2>(mix_, r, J, {3, 3});
    return true;
  }

 private:
  SE2 z_;
  Eigen::Vector3d sigma_;
  Eigen::Matrix3d mix_;
  bool mixed_;
};

// A DR edge whose yaw drifts with the heading: the rate is the third parameter block.
class DriftingPoseCost final : public ceres::SizedCostFunction<3, 3, 3, 1> {
 public:
  explicit DriftingPoseCost(const GraphEdge& e) : e_(e), mixed_(!e.mix.isIdentity(0.0)) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    drifting_pose_residual(p[0], p[1], e_, p[2][0], r, J ? J[0] : nullptr, J ? J[1] : nullptr,
                           J ? J[2] : nullptr);
    if (mixed_) apply_mix<3>(e_.mix, r, J, {3, 3, 1});
    return true;
  }

 private:
  GraphEdge e_;
  bool mixed_;
};

// Zero-mean prior on the drift rate.
class DriftPriorCost final : public ceres::SizedCostFunction<1, 1> {
 public:
  explicit DriftPriorCost(double sigma) : inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    r[0] = inv_sigma_ * p[0][0];
    if (J != nullptr && J[0] != nullptr) J[0][0] = inv_sigma_;
    return true;
  }

 private:
  double inv_sigma_;
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

// The edge's robust loss (owned by the problem), or nullptr for least squares.
ceres::LossFunction* loss_of(const GraphEdge& e) {
  if (e.loss_scale <= 0.0) return nullptr;
  switch (e.loss) {
    case GraphEdge::Loss::kNone: return nullptr;
    case GraphEdge::Loss::kHuber: return new ceres::HuberLoss(e.loss_scale);
    case GraphEdge::Loss::kCauchy: return new ceres::CauchyLoss(e.loss_scale);
  }
  return nullptr;
}

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
  opt.initial_trust_region_radius = config.initial_trust_region_radius;
  return opt;
}

// Ends the solve after a successful step whose cost decrease the linear model predicted to
// within `tolerance` (PoseGraphConfig::model_agreement_stop).
class ModelAgreementStop final : public ceres::IterationCallback {
 public:
  explicit ModelAgreementStop(double tolerance) : tolerance_(tolerance) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (s.iteration > 0 && s.step_is_successful && std::abs(1.0 - s.relative_decrease) < tolerance_) {
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double tolerance_;
};

ceres::Problem::Options problem_options() {
  ceres::Problem::Options popt;
  popt.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  popt.enable_fast_removal = false;
  // Every block and residual here is built by this file with the right sizes: Ceres'
  // per-residual checks (a linear scan of the block's parameters) are skipped.
  popt.disable_all_safety_checks = true;
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
                                  const PoseGraphConfig& config, HeadingDrift* drift) {
  if (config.linear_solver == PoseGraphConfig::LinearSolver::kChainPcg)
    return solve_pose_graph_pcg(poses, prior, prior_sigma, edges, config, drift);
  PoseGraphSummary out;
  if (poses.empty()) return out;
  const bool drifting = drift != nullptr && drift->prior_sigma_rad_s > 0.0;
  double rate = drifting ? drift->rate_rad_s : 0.0;
  std::vector<std::array<double, 3>> x(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) x[i] = {poses[i].x, poses[i].y, poses[i].theta};

  ceres::Problem problem(problem_options());
  for (auto& p : x) problem.AddParameterBlock(p.data(), 3);
  problem.AddResidualBlock(new PosePriorCost(prior, prior_sigma), nullptr, x[0].data());
  if (drifting) problem.AddResidualBlock(new DriftPriorCost(drift->prior_sigma_rad_s), nullptr, &rate);
  for (const GraphEdge& e : edges) {
    double* a = x[static_cast<size_t>(e.from)].data();
    double* b = x[static_cast<size_t>(e.to)].data();
    if (drifting && e.dt_s != 0.0) {
      problem.AddResidualBlock(new DriftingPoseCost(e), loss_of(e), a, b, &rate);
    } else {
      problem.AddResidualBlock(new RelativePoseCost(drift_corrected(e, rate), e.sigma, e.mix), loss_of(e), a, b);
    }
  }
  ceres::Solver::Options options = solver_options(config);
  ModelAgreementStop stop(config.model_agreement_stop);
  if (config.model_agreement_stop > 0.0) options.callbacks.push_back(&stop);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  out = summarise(summary);
  if (out.usable && drifting) drift->rate_rad_s = rate;
  if (out.usable) {
    for (size_t i = 0; i < poses.size(); ++i) {
      poses[i] = {x[i][0], x[i][1], wrap_angle(x[i][2])};
    }
  }
  return out;
}

double edge_whitened_norm(const std::vector<SE2>& poses, const GraphEdge& e, double rate_rad_s) {
  const SE2& A = poses[static_cast<size_t>(e.from)];
  const SE2& B = poses[static_cast<size_t>(e.to)];
  const double a[3] = {A.x, A.y, A.theta}, b[3] = {B.x, B.y, B.theta};
  Eigen::Vector3d r;
  relative_pose_residual(a, b, drift_corrected(e, rate_rad_s), e.sigma, r.data(), nullptr, nullptr);
  return (e.mix * r).norm();
}

const char* linear_solver_name(PoseGraphConfig::LinearSolver s) {
  return s == PoseGraphConfig::LinearSolver::kChainPcg ? "chain_pcg" : "sparse_cholesky";
}

const char* loss_name(GraphEdge::Loss loss) {
  switch (loss) {
    case GraphEdge::Loss::kNone: return "none";
    case GraphEdge::Loss::kHuber: return "huber";
    case GraphEdge::Loss::kCauchy: return "cauchy";
  }
  return "none";
}

double robust_weight(GraphEdge::Loss loss, double scale, double whitened_norm) {
  if (scale <= 0.0) return 1.0;
  switch (loss) {
    case GraphEdge::Loss::kNone: return 1.0;
    case GraphEdge::Loss::kHuber: return whitened_norm <= scale ? 1.0 : scale / whitened_norm;
    case GraphEdge::Loss::kCauchy: return 1.0 / (1.0 + (whitened_norm * whitened_norm) / (scale * scale));
  }
  return 1.0;
}

PoseGraphSummary solve_leaf_pose(std::vector<SE2>& poses, int leaf,
                                 const std::vector<GraphEdge>& edges,
                                 const PoseGraphConfig& config, double drift_rate_rad_s) {
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
    problem.AddResidualBlock(new RelativePoseCost(drift_corrected(e, drift_rate_rad_s), e.sigma, e.mix),
                             loss_of(e), block(e.from), block(e.to));
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
