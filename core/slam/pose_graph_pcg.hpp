#pragma once
// The full pose-graph solve without a sparse factorisation (PoseGraphConfig::LinearSolver::
// kChainPcg): Levenberg-Marquardt whose normal equations are solved by conjugate gradients
// preconditioned with the odometry chain.
//
// Why: a survey that flies the same route R times closes loops between laps, so the graph's
// best elimination ordering still leaves separators of about 2R poses (cut the route's ring
// at two places) and a sparse Cholesky factor fills in: at 5,000 keyframes and 3,778 loops
// Eigen's simplicial LDLT took 410 ms per factorisation (1.5 million non-zeros). The
// keyframes' consecutive edges (DR odometry, sequential scan matches) make a chain whose
// normal equations are block tridiagonal and solve in O(n); every other edge (loop closures,
// heading links) keeps its diagonal blocks in the preconditioner and drops its coupling,
// which keeps the preconditioner positive definite (the block diagonal of a positive
// semi-definite term is positive semi-definite). A warm-started re-solve then converges in
// tens of CG iterations of O(edges) each (docs/BENCHMARKS.md "Long missions").
//
// Deterministic: one thread, every sum in a fixed order. If CG does not reach its tolerance
// in PoseGraphConfig::pcg_max_iterations, that step is solved by Eigen's sparse LDLT on the
// same matrix instead (PoseGraphSummary::direct_fallbacks counts them).
#include <vector>

#include "core/slam/pose_graph.hpp"

namespace orthosonar::slam {

PoseGraphSummary solve_pose_graph_pcg(std::vector<SE2>& poses, const SE2& prior,
                                      const Eigen::Vector3d& prior_sigma,
                                      const std::vector<GraphEdge>& edges,
                                      const PoseGraphConfig& config, HeadingDrift* drift);

// Ceres' loss functions' ρ(s) at a squared whitened residual norm s, as Ceres defines them
// (HuberLoss(a), CauchyLoss(a)); kNone or scale <= 0: s. Its derivative ρ'(s) is
// robust_weight(loss, scale, √s) (pose_graph.hpp).
double loss_rho(GraphEdge::Loss loss, double scale, double s);

}  // namespace orthosonar::slam
