#include "core/slam/pcm.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <Eigen/Cholesky>

namespace orthosonar::slam {

UncertainSE2 compose(const UncertainSE2& a_b, const UncertainSE2& b_c) {
  const double c = std::cos(a_b.T.theta), s = std::sin(a_b.T.theta);
  const double x2 = b_c.T.x, y2 = b_c.T.y;
  Eigen::Matrix3d J1 = Eigen::Matrix3d::Identity();
  J1(0, 2) = -s * x2 - c * y2;
  J1(1, 2) = c * x2 - s * y2;
  Eigen::Matrix3d J2 = Eigen::Matrix3d::Identity();
  J2(0, 0) = c;
  J2(0, 1) = -s;
  J2(1, 0) = s;
  J2(1, 1) = c;
  UncertainSE2 out;
  out.T = a_b.T * b_c.T;
  out.cov = J1 * a_b.cov * J1.transpose() + J2 * b_c.cov * J2.transpose();
  return out;
}

UncertainSE2 inverse(const UncertainSE2& a_b) {
  const double c = std::cos(a_b.T.theta), s = std::sin(a_b.T.theta);
  const double x = a_b.T.x, y = a_b.T.y;
  Eigen::Matrix3d J;
  J << -c, -s, s * x - c * y,  //
      s, -c, c * x + s * y,    //
      0.0, 0.0, -1.0;
  UncertainSE2 out;
  out.T = a_b.T.inverse();
  out.cov = J * a_b.cov * J.transpose();
  return out;
}

double squared_mahalanobis(const Eigen::Vector3d& d, const Eigen::Matrix3d& cov) { return d.dot(cov.ldlt().solve(d)); }

double cycle_mahalanobis2(const UncertainSE2& z_i, const UncertainSE2& T_bi_bj,
                          const UncertainSE2& z_j, const UncertainSE2& T_aj_ai) {
  const UncertainSE2 cycle = compose(compose(compose(z_i, T_bi_bj), inverse(z_j)), T_aj_ai);
  const Eigen::Vector3d e(cycle.T.x, cycle.T.y, wrap_angle(cycle.T.theta));
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(cycle.cov);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return INFINITY;
  return e.dot(ldlt.solve(e));
}

Adjacency pcm_consistency(const std::vector<LoopCandidate>& candidates, const OdometryFn& odometry,
                          double threshold) {
  const size_t n = candidates.size();
  Adjacency adj(n, std::vector<bool>(n, false));
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      const LoopCandidate& ca = candidates[a];
      const LoopCandidate& cb = candidates[b];
      const double m2 = cycle_mahalanobis2(ca.z, odometry(ca.to, cb.to), cb.z, odometry(cb.from, ca.from));
      adj[a][b] = adj[b][a] = m2 < threshold;
    }
  }
  return adj;
}

namespace {

bool better(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return a.size() > b.size();
  return a < b;  // both sorted: lexicographically smaller wins
}

// Bron–Kerbosch with pivoting (Tomita): R the clique so far, P candidates, X excluded.
void bron_kerbosch(const Adjacency& adj, std::vector<int>& R, std::vector<int> P, std::vector<int> X,
                   std::vector<int>& best) {
  if (P.empty() && X.empty()) {
    std::vector<int> clique = R;
    std::sort(clique.begin(), clique.end());
    if (better(clique, best)) best = clique;
    return;
  }
  if (R.size() + P.size() < best.size()) return;  // cannot beat the best (ties still explored)
  // Pivot: the vertex of P ∪ X with the most neighbours in P (lowest index on ties).
  int pivot = -1;
  size_t most = 0;
  for (const auto* set : {&P, &X}) {
    for (int u : *set) {
      size_t n = 0;
      for (int v : P) n += adj[static_cast<size_t>(u)][static_cast<size_t>(v)] ? 1 : 0;
      if (pivot < 0 || n > most || (n == most && u < pivot)) {
        pivot = u;
        most = n;
      }
    }
  }
  std::vector<int> order;
  for (int v : P) {
    if (!adj[static_cast<size_t>(pivot)][static_cast<size_t>(v)]) order.push_back(v);
  }
  for (int v : order) {
    std::vector<int> P2, X2;
    for (int u : P) {
      if (u != v && adj[static_cast<size_t>(v)][static_cast<size_t>(u)]) P2.push_back(u);
    }
    for (int u : X) {
      if (adj[static_cast<size_t>(v)][static_cast<size_t>(u)]) X2.push_back(u);
    }
    R.push_back(v);
    bron_kerbosch(adj, R, std::move(P2), std::move(X2), best);
    R.pop_back();
    P.erase(std::find(P.begin(), P.end(), v));
    X.push_back(v);
  }
}

}  // namespace

std::vector<int> maximum_clique(const Adjacency& adjacency) {
  const int n = static_cast<int>(adjacency.size());
  std::vector<int> best, R, P, X;
  for (int i = 0; i < n; ++i) P.push_back(i);
  bron_kerbosch(adjacency, R, P, X, best);
  return best;
}

std::vector<int> maximum_clique_brute_force(const Adjacency& adjacency) {
  const int n = static_cast<int>(adjacency.size());
  assert(n <= 20);
  std::vector<int> best;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<int> set;
    for (int i = 0; i < n; ++i) {
      if (mask & (1u << i)) set.push_back(i);
    }
    bool clique = true;
    for (size_t a = 0; a < set.size() && clique; ++a) {
      for (size_t b = a + 1; b < set.size() && clique; ++b) {
        clique = adjacency[static_cast<size_t>(set[a])][static_cast<size_t>(set[b])];
      }
    }
    if (clique && better(set, best)) best = set;
  }
  return best;
}

}  // namespace orthosonar::slam
