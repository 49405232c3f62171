#pragma once
// SE(2) pose graph on Ceres (SPEC §5): relative-pose residuals weighted by the square-root
// information (diagonal sigmas), analytic Jacobians, first pose anchored by a prior.
// Single-threaded with every option set explicitly, so results are bit-reproducible.
// Eigen's sparse Cholesky (simplicial LDLT) solves the normal equations.
// Ceres stays out of this header (its glog CHECK macro would clash with Catch's).
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace orthosonar::slam {

struct PoseGraphConfig {
  int max_iterations = 20;           // warm-started re-solves converge in a few
  // Ceres' default. 1e-10 took 8 iterations instead of 5 to re-solve a 1000-keyframe graph
  // after a loop closure, for pose changes below a micrometre (docs/BENCHMARKS.md).
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-10;
  // Levenberg-Marquardt's first trust region (Ceres' default 1e4). A warm-started re-solve
  // starts next to its optimum, where the Gauss-Newton step is good: a larger region takes
  // it at once. 1e8 re-solved a 1000-keyframe graph after a loop closure in 3 iterations
  // instead of 5 (docs/BENCHMARKS.md).
  double initial_trust_region_radius = 1e8;
  // Stop after a step whose actual cost decrease matched the linearised model's prediction
  // to within this fraction (|1 - rho| below it): the cost is locally quadratic there, so
  // that step reached the optimum and a further one would only confirm it. Saves the
  // confirming factorisation of a warm-started re-solve. 0: off (Ceres' tolerances alone).
  double model_agreement_stop = 5e-2;  // measured: docs/BENCHMARKS.md
  // How the full solve's normal equations are solved. kChainPcg (core/slam/pose_graph_pcg.hpp):
  // conjugate gradients preconditioned by the odometry chain, cost O(edges) per CG
  // iteration; the solve at 5,000 keyframes in 12.8 ms instead of 351 ms (docs/BENCHMARKS.md).
  // kSparseCholesky: Ceres' Levenberg-Marquardt on Eigen's sparse LDLT, the reference (and
  // the solver of every release before 2026-12-07).
  enum class LinearSolver { kChainPcg, kSparseCholesky } linear_solver = LinearSolver::kChainPcg;
  // CG ends when the preconditioned residual norm sqrt(rᵀM⁻¹r) has fallen by this factor
  // from the step's first; the poses then agree with the direct solve's to 1e-8 m or
  // better (docs/SLAM.md "The full solve's linear algebra").
  double pcg_tolerance = 1e-9;
  int pcg_max_iterations = 1000;  // beyond: the step is solved by sparse LDLT instead
};

// "chain_pcg", "sparse_cholesky": the configuration's names of LinearSolver.
const char* linear_solver_name(PoseGraphConfig::LinearSolver s);
inline constexpr PoseGraphConfig::LinearSolver kLinearSolvers[] = {PoseGraphConfig::LinearSolver::kChainPcg,
                                                                   PoseGraphConfig::LinearSolver::kSparseCholesky};

// A heading that drifts at a steady rate (a gyro's bias, the slow drift of an AHRS) makes
// every dead-reckoning yaw increment too large by rate × dt. With prior_sigma_rad_s > 0 the
// rate is one more unknown of the graph, with a zero-mean prior of that sigma; the edges
// that carry dt_s > 0 (the DR factors) are corrected by it. 0: no drift state.
struct HeadingDrift {
  double rate_rad_s = 0.0;         // the estimate: warm start in, solution out
  double prior_sigma_rad_s = 0.0;
};

struct GraphEdge {
  int from = 0;
  int to = 0;
  SE2 T_from_to;
  Eigen::Vector3d sigma{0.1, 0.1, 0.01};  // x, y (m), theta (rad)
  // Applied to the whitened residual diag(1/sigma) e: r = mix diag(1/sigma) e, so the
  // information is diag(1/sigma) mixᵀ mix diag(1/sigma). Identity: the diagonal sigmas as
  // they are; a scan match with unobserved directions weakens them (keyframe_slam.cpp).
  Eigen::Matrix3d mix = Eigen::Matrix3d::Identity();
  // Duration of the motion (s) when its yaw drifts with the heading (HeadingDrift): the
  // expected yaw change is T_from_to.theta - rate * dt_s. 0: no drift (scan matches).
  double dt_s = 0.0;
  // Robust loss on the whitened residual (Ceres' loss functions): above `loss_scale` (its
  // norm) a Huber edge grows linearly, a Cauchy edge logarithmically, so a wrong loop
  // closure that got into the graph pulls with a bounded force. kNone: least squares.
  enum class Loss { kNone, kHuber, kCauchy } loss = Loss::kNone;
  double loss_scale = 0.0;
};

struct PoseGraphSummary {
  bool usable = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int linear_iterations = 0;  // CG iterations over the solve (kChainPcg)
  int direct_fallbacks = 0;   // steps CG did not converge on, solved by sparse LDLT instead
};

// Residual of a relative-pose measurement z = T_from_to between poses a = T_W_from and
// b = T_W_to, each stored as (x, y, theta):
//   r_xy = S_xy R(z)^T (R(a)^T (t_b - t_a) - t_z),  r_theta = S_theta wrap(θb - θa - θz)
// with S = diag(1 / sigma). J_a, J_b (row-major 3x3) are written when not null; these
// analytic Jacobians are what the Ceres cost function returns.
void relative_pose_residual(const double* a, const double* b, const SE2& z,
                            const Eigen::Vector3d& sigma, double* residual, double* J_a,
                            double* J_b);
// The same, with cos and sin of a's heading and of z's given: a solver computes them once
// per pose and once per edge instead of once per edge and evaluation.
struct HeadingTrig {
  double cos_a, sin_a, cos_z, sin_z;
};
void relative_pose_residual(const double* a, const double* b, const SE2& z, const HeadingTrig& trig,
                            const Eigen::Vector3d& sigma, double* residual, double* J_a, double* J_b);
// Prior on one pose: r = S (R(p)^T (t - t_p), wrap(θ - θp)).
void pose_prior_residual(const double* x, const SE2& prior, const Eigen::Vector3d& sigma,
                         double* residual, double* J_x);

// The measurement an edge predicts at drift rate `rate`: its yaw less rate * dt_s.
SE2 drift_corrected(const GraphEdge& e, double rate_rad_s);

// The residual of relative_pose_residual for drift_corrected(e, rate), and its derivative
// with respect to the rate (3 values) when J_rate is not null.
void drifting_pose_residual(const double* a, const double* b, const GraphEdge& e, double rate_rad_s,
                            double* residual, double* J_a, double* J_b, double* J_rate);

// Optimises `poses` in place (they are the warm start). Pose 0 carries the prior. The
// normal equations are solved as config.linear_solver says. With
// drift->prior_sigma_rad_s > 0 the drift rate is estimated too (drift->rate_rad_s in and out).
// Edges with a robust loss (GraphEdge::loss) get Ceres' loss function (kSparseCholesky) or
// its weight ρ' as iteratively reweighted least squares, which has the same optimum (kChainPcg).
PoseGraphSummary solve_pose_graph(std::vector<SE2>& poses, const SE2& prior,
                                  const Eigen::Vector3d& prior_sigma,
                                  const std::vector<GraphEdge>& edges,
                                  const PoseGraphConfig& config, HeadingDrift* drift = nullptr);

// "none", "huber", "cauchy": the configuration's names of GraphEdge::Loss.
const char* loss_name(GraphEdge::Loss loss);
inline constexpr GraphEdge::Loss kLosses[] = {GraphEdge::Loss::kNone, GraphEdge::Loss::kHuber, GraphEdge::Loss::kCauchy};

// An edge's whitened residual norm |mix diag(1/sigma) e| at `poses` (drift_corrected by the rate).
double edge_whitened_norm(const std::vector<SE2>& poses, const GraphEdge& e, double rate_rad_s = 0.0);
// The iteratively-reweighted-least-squares weight of a loss at a whitened residual norm u:
// ρ'(u²) (Huber: min(1, scale / u); Cauchy: 1 / (1 + u² / scale²)). A least-squares edge whose
// squared residual is multiplied by it has, at that residual, the loss's gradient.
double robust_weight(GraphEdge::Loss loss, double scale, double whitened_norm);

// Optimises one pose, `leaf`, over the edges that touch it, every other pose held where it
// is. When a new keyframe is joined to the graph only through edges to poses already
// optimised (no new loop closure), the full problem's optimum is the old one plus this
// leaf's: the leaf can meet its own edges' weighted optimum wherever its neighbours are.
// A drift rate, when given, is held too (edges drift_corrected by it).
PoseGraphSummary solve_leaf_pose(std::vector<SE2>& poses, int leaf,
                                 const std::vector<GraphEdge>& edges,
                                 const PoseGraphConfig& config, double drift_rate_rad_s = 0.0);

}  // namespace orthosonar::slam
