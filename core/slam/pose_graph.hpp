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
};

struct PoseGraphSummary {
  bool usable = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

// Residual of a relative-pose measurement z = T_from_to between poses a = T_W_from and
// b = T_W_to, each stored as (x, y, theta):
//   r_xy = S_xy R(z)^T (R(a)^T (t_b - t_a) - t_z),  r_theta = S_theta wrap(θb - θa - θz)
// with S = diag(1 / sigma). J_a, J_b (row-major 3x3) are written when not null; these
// analytic Jacobians are what the Ceres cost function returns.
void relative_pose_residual(const double* a, const double* b, const SE2& z,
                            const Eigen::Vector3d& sigma, double* residual, double* J_a,
                            double* J_b);
// Prior on one pose: r = S (R(p)^T (t - t_p), wrap(θ - θp)).
void pose_prior_residual(const double* x, const SE2& prior, const Eigen::Vector3d& sigma,
                         double* residual, double* J_x);

// Optimises `poses` in place (they are the warm start). Pose 0 carries the prior.
PoseGraphSummary solve_pose_graph(std::vector<SE2>& poses, const SE2& prior,
                                  const Eigen::Vector3d& prior_sigma,
                                  const std::vector<GraphEdge>& edges,
                                  const PoseGraphConfig& config);

// Optimises one pose, `leaf`, over the edges that touch it, every other pose held where it
// is. When a new keyframe is joined to the graph only through edges to poses already
// optimised (no new loop closure), the full problem's optimum is the old one plus this
// leaf's: the leaf can meet its own edges' weighted optimum wherever its neighbours are.
PoseGraphSummary solve_leaf_pose(std::vector<SE2>& poses, int leaf,
                                 const std::vector<GraphEdge>& edges,
                                 const PoseGraphConfig& config);

}  // namespace orthosonar::slam
