#pragma once
// Pairwise Consistency Maximization (Mangelson et al., ICRA 2018) for loop closures
// (SPEC §5): two loop closures are consistent when the cycle they close with the
// odometry between their ends has a squared Mahalanobis norm below a chi-square
// threshold; the largest mutually consistent set is an exact maximum clique.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace orthosonar::slam {

// A relative pose with its 3x3 covariance in (x, y, theta).
struct UncertainSE2 {
  SE2 T;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
};

// First-order compounding (Smith, Self & Cheeseman): (T_a_b, Σ1) ⊕ (T_b_c, Σ2).
UncertainSE2 compose(const UncertainSE2& a_b, const UncertainSE2& b_c);
UncertainSE2 inverse(const UncertainSE2& a_b);

// dᵀ cov⁻¹ d (cov by LDLT): the gates of scan matches against DR and of loops against the
// odometry chain.
double squared_mahalanobis(const Eigen::Vector3d& d, const Eigen::Matrix3d& cov);

// Squared Mahalanobis norm of the cycle a_i -> b_i -> b_j -> a_j -> a_i, where
// z_i = T_{a_i b_i} and z_j = T_{a_j b_j} are loop closures, T_bi_bj and T_aj_ai come from
// the odometry (current estimates with their chain covariance).
double cycle_mahalanobis2(const UncertainSE2& z_i, const UncertainSE2& T_bi_bj,
                          const UncertainSE2& z_j, const UncertainSE2& T_aj_ai);

// Symmetric boolean adjacency (diagonal ignored).
using Adjacency = std::vector<std::vector<bool>>;

// A loop-closure candidate: measured T_{from to} (from = old keyframe, to = new one).
struct LoopCandidate {
  int from = 0;
  int to = 0;
  UncertainSE2 z;
};
// Relative pose between two graph nodes from the odometry (value and chain covariance).
using OdometryFn = std::function<UncertainSE2(int from, int to)>;

// PCM consistency graph: candidates i and j are adjacent when the squared Mahalanobis norm
// of their cycle is below `threshold` (11.34 = chi-square 0.99 with 3 dof).
Adjacency pcm_consistency(const std::vector<LoopCandidate>& candidates, const OdometryFn& odometry,
                          double threshold);

// Exact maximum clique by Bron–Kerbosch with pivoting. Among cliques of maximum size the
// lexicographically smallest sorted vertex list is returned (deterministic). Empty graph
// gives an empty clique.
std::vector<int> maximum_clique(const Adjacency& adjacency);
// The same answer by enumerating every subset (for tests; n <= 20).
std::vector<int> maximum_clique_brute_force(const Adjacency& adjacency);

}  // namespace orthosonar::slam
