#include "core/slam/pose_graph_pcg.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

namespace orthosonar::slam {

double loss_rho(GraphEdge::Loss loss, double scale, double s) {
  if (scale <= 0.0) return s;
  const double b = scale * scale;
  switch (loss) {
    case GraphEdge::Loss::kNone: return s;
    case GraphEdge::Loss::kHuber: return s <= b ? s : 2.0 * std::sqrt(b * s) - b;
    case GraphEdge::Loss::kCauchy: return b * std::log1p(s / b);
  }
  return s;
}

namespace {

using M3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;
using RowM3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;

// y ± A x or y ± Aᵀ x for a 3x3 block (column-major, Eigen's default) and 3-vectors given
// by pointer: the CG loop's products, written out so they inline.
template <bool kTransposed, bool kSubtract>
inline void block_mv(const M3& A, const double* x, double* y) {
  const double* a = A.data();
  const double x0 = x[0], x1 = x[1], x2 = x[2];
  for (int i = 0; i < 3; ++i) {
    const double v = kTransposed ? a[3 * i] * x0 + a[3 * i + 1] * x1 + a[3 * i + 2] * x2
                                 : a[i] * x0 + a[i + 3] * x1 + a[i + 6] * x2;
    y[i] = kSubtract ? y[i] - v : y[i] + v;
  }
}
constexpr auto add_mv = block_mv<false, false>;
constexpr auto sub_mv = block_mv<false, true>;
constexpr auto add_mtv = block_mv<true, false>;
constexpr auto sub_mtv = block_mv<true, true>;

// The unknowns: 3 per pose (x, y, theta, added linearly as Ceres does), and the drift rate.
struct State {
  std::vector<V3> pose;
  double rate = 0.0;
  std::vector<std::array<double, 2>> trig;  // cos, sin of each pose's heading (refresh_trig)
};

void refresh_trig(State& x) {
  x.trig.resize(x.pose.size());
  for (size_t i = 0; i < x.pose.size(); ++i) x.trig[i] = {std::cos(x.pose[i][2]), std::sin(x.pose[i][2])};
}

// The problem as solve_pose_graph states it.
struct Problem {
  const SE2& prior;
  const V3& prior_sigma;
  const std::vector<GraphEdge>& edges;
  bool drifting = false;
  double rate_sigma = 0.0;
  // Per edge, once per solve: cos and sin of the measured heading change, and whether the
  // edge mixes its residual (GraphEdge::mix not the identity).
  std::vector<std::array<double, 2>> z_trig;
  std::vector<char> mixed;
};

// One edge's residual r (mixed) and Jacobians: A for pose `from`, B for `to`, c for the rate.
struct EdgeLinearisation {
  V3 r;
  M3 A, B;
  V3 c = V3::Zero();
};

bool drifts(const Problem& p, const GraphEdge& e) { return p.drifting && e.dt_s != 0.0; }

EdgeLinearisation linearise(const Problem& p, const State& x, size_t i, bool jacobians) {
  const GraphEdge& e = p.edges[i];
  EdgeLinearisation l;
  const V3& a = x.pose[static_cast<size_t>(e.from)];
  const V3& b = x.pose[static_cast<size_t>(e.to)];
  RowM3 Ja, Jb;
  double* ja = jacobians ? Ja.data() : nullptr;
  double* jb = jacobians ? Jb.data() : nullptr;
  if (drifts(p, e)) {
    drifting_pose_residual(a.data(), b.data(), e, x.rate, l.r.data(), ja, jb, jacobians ? l.c.data() : nullptr);
  } else {
    // Not drifting: z is the edge's measurement as it is (drift_corrected leaves it).
    const auto& ta = x.trig[static_cast<size_t>(e.from)];
    const auto& tz = p.z_trig[i];
    relative_pose_residual(a.data(), b.data(), e.T_from_to, {ta[0], ta[1], tz[0], tz[1]}, e.sigma, l.r.data(), ja, jb);
  }
  if (!p.mixed[i]) {
    if (jacobians) {
      l.A = Ja;
      l.B = Jb;
    }
    return l;
  }
  l.r = (e.mix * l.r).eval();
  if (jacobians) {
    l.A = e.mix * Ja;
    l.B = e.mix * Jb;
    l.c = (e.mix * l.c).eval();
  }
  return l;
}

// 0.5 Σ ρ(|r|²), as Ceres counts cost.
double cost(const Problem& p, const State& x) {
  double sum = 0.0;
  V3 r;
  pose_prior_residual(x.pose[0].data(), p.prior, p.prior_sigma, r.data(), nullptr);
  sum += r.squaredNorm();
  if (p.drifting) sum += (x.rate / p.rate_sigma) * (x.rate / p.rate_sigma);
  for (size_t i = 0; i < p.edges.size(); ++i) {
    const double s = linearise(p, x, i, false).r.squaredNorm();
    sum += loss_rho(p.edges[i].loss, p.edges[i].loss_scale, s);
  }
  return 0.5 * sum;
}

// The Gauss-Newton normal equations at one state, block by block: H = Jᵀ W J, g = Jᵀ W r,
// with W the robust weights ρ'(s) (iteratively reweighted least squares).
struct Normal {
  std::vector<M3> diag;        // H_kk
  std::vector<M3> off;         // H_{from,to} of each edge off the chain, in edge order
  std::vector<V3> pose_rate;   // H_{k,rate}
  double rate_rate = 0.0;      // H_{rate,rate}
  std::vector<V3> g;           // per pose
  double g_rate = 0.0;
  // The preconditioner's share: chain_off[k] = Σ H_{k,k+1} over the edges joining k and k+1
  // (from k's side), chain_rate[k] the rate couplings of those edges only.
  std::vector<M3> chain_off;
  std::vector<V3> chain_rate;
  // The first unknown of `from` and of `to` (3 from, 3 to) of each edge in `off`. The chain
  // edges are summed into chain_off (the DR and the scan-match factor of two consecutive
  // keyframes make one block); an edge from a pose to itself is all on the diagonal.
  std::vector<std::array<int, 2>> ends;
};

// Fills `ne` (its buffers are reused from one linearisation to the next).
void normal_equations(const Problem& p, const State& x, Normal& ne) {
  const size_t n = x.pose.size();
  ne.rate_rate = 0.0;
  ne.g_rate = 0.0;
  ne.ends.clear();
  ne.off.clear();
  ne.diag.assign(n, M3::Zero());
  ne.pose_rate.assign(n, V3::Zero());
  ne.g.assign(n, V3::Zero());
  ne.chain_off.assign(n, M3::Zero());
  ne.chain_rate.assign(n, V3::Zero());
  {
    V3 r;
    RowM3 J;
    pose_prior_residual(x.pose[0].data(), p.prior, p.prior_sigma, r.data(), J.data());
    ne.diag[0] += J.transpose() * J;
    ne.g[0] += J.transpose() * r;
  }
  if (p.drifting) {
    const double inv = 1.0 / p.rate_sigma;
    ne.rate_rate += inv * inv;
    ne.g_rate += inv * (inv * x.rate);
  }
  for (size_t i = 0; i < p.edges.size(); ++i) {
    const GraphEdge& e = p.edges[i];
    const EdgeLinearisation l = linearise(p, x, i, true);
    const double w = robust_weight(e.loss, e.loss_scale, l.r.norm());  // ρ'(|r|²)
    const size_t a = static_cast<size_t>(e.from), b = static_cast<size_t>(e.to);
    if (a == b) {
      const M3 J = l.A + l.B;
      ne.diag[a] += w * (J.transpose() * J);
      ne.g[a] += w * (J.transpose() * l.r);
      if (drifts(p, e)) ne.pose_rate[a] += w * (J.transpose() * l.c);
    } else {
      ne.diag[a] += w * (l.A.transpose() * l.A);
      ne.diag[b] += w * (l.B.transpose() * l.B);
      const M3 off = w * (l.A.transpose() * l.B);
      ne.g[a] += w * (l.A.transpose() * l.r);
      ne.g[b] += w * (l.B.transpose() * l.r);
      const bool chain = a + 1 == b || b + 1 == a;
      if (chain) {
        ne.chain_off[std::min(a, b)] += a < b ? off : M3(off.transpose());
      } else {
        ne.off.push_back(off);
        ne.ends.push_back({3 * e.from, 3 * e.to});
      }
      if (drifts(p, e)) {
        const V3 ca = w * (l.A.transpose() * l.c), cb = w * (l.B.transpose() * l.c);
        ne.pose_rate[a] += ca;
        ne.pose_rate[b] += cb;
        if (chain) {
          ne.chain_rate[a] += ca;
          ne.chain_rate[b] += cb;
        }
      }
    }
    if (drifts(p, e)) {
      ne.rate_rate += w * l.c.squaredNorm();
      ne.g_rate += w * l.c.dot(l.r);
    }
  }
}

// A vector over the unknowns: 3 per pose, then the rate when drifting.
using Vec = Eigen::VectorXd;

// (H + D) v, D the Levenberg-Marquardt damping on the diagonal.
struct Operator {
  const Problem& p;
  const Normal& ne;
  const Vec& damping;
  // out = (H + D) v.
  void apply(const Vec& v, Vec& out) const {
    const size_t n = ne.diag.size();
    const double* vp = v.data();
    double* op = out.data();
    for (size_t k = 0; k < n; ++k) {  // the diagonal and the chain
      double* o = op + 3 * k;
      const double* x = vp + 3 * k;
      const double* d = damping.data() + 3 * k;
      o[0] = d[0] * x[0];
      o[1] = d[1] * x[1];
      o[2] = d[2] * x[2];
      add_mv(ne.diag[k], x, o);
      if (k > 0) add_mtv(ne.chain_off[k - 1], x - 3, o);
      if (k + 1 < n) add_mv(ne.chain_off[k], x + 3, o);
    }
    for (size_t e = 0; e < ne.ends.size(); ++e) {  // the rest
      const auto [a, b] = ne.ends[e];
      add_mv(ne.off[e], vp + b, op + a);
      add_mtv(ne.off[e], vp + a, op + b);
    }
    if (p.drifting) {
      const size_t r = 3 * n;
      double s = (ne.rate_rate + damping[static_cast<Eigen::Index>(r)]) * vp[r];
      for (size_t k = 0; k < n; ++k) {
        const V3& c = ne.pose_rate[k];
        double* o = op + 3 * k;
        const double* x = vp + 3 * k;
        o[0] += c[0] * vp[r];
        o[1] += c[1] * vp[r];
        o[2] += c[2] * vp[r];
        s += c[0] * x[0] + c[1] * x[1] + c[2] * x[2];
      }
      op[r] = s;
    }
  }
};

// M: the chain's block-tridiagonal part of H + D (every diagonal block whole, the
// off-diagonal blocks of consecutive poses only), bordered by the chain edges' rate
// couplings. Factorised once per step (block LDLᵀ), solved in O(n).
class ChainPreconditioner {
 public:
  bool factorise(const Normal& ne, const Vec& damping, bool drifting) {
    // A twisted block factorisation: the chain is eliminated from both ends towards the
    // middle pose m. The substitutions are serial recurrences bound by the latency of one
    // 3x3 product after the other; from both ends they are two independent recurrences,
    // which one core runs side by side. Exact: the same T as a one-way factorisation.
    //   top, k < m:    S_k = D_k - C_{k-1}ᵀ S_{k-1}⁻¹ C_{k-1},  link_k = S_k⁻¹ C_k
    //   bottom, k > m: P_k = D_k - C_k P_{k+1}⁻¹ C_kᵀ,          link_k = P_k⁻¹ C_{k-1}ᵀ
    //   middle:        Σ = D_m - C_{m-1}ᵀ S_{m-1}⁻¹ C_{m-1} - C_m P_{m+1}⁻¹ C_mᵀ
    // (D: diagonal blocks with the damping, C_k: the block between poses k and k + 1).
    const size_t n = ne.diag.size();
    middle_ = n / 2;
    inv_.resize(n);
    link_.assign(n, M3::Zero());
    const auto pivot = [&](size_t k, const M3& less) {
      M3 S = ne.diag[k];
      S.diagonal() += damping.segment<3>(static_cast<Eigen::Index>(3 * k));
      S -= less;
      Eigen::LLT<M3> llt(S);
      if (llt.info() != Eigen::Success) return false;
      inv_[k] = llt.solve(M3::Identity());
      return true;
    };
    const M3 none = M3::Zero();
    for (size_t k = 0; k < middle_; ++k) {
      if (!pivot(k, k > 0 ? M3(ne.chain_off[k - 1].transpose() * link_[k - 1]) : none)) return false;
      link_[k] = inv_[k] * ne.chain_off[k];
    }
    for (size_t k = n; k-- > middle_ + 1;) {
      if (!pivot(k, k + 1 < n ? M3(ne.chain_off[k] * link_[k + 1]) : none)) return false;
      link_[k] = inv_[k] * ne.chain_off[k - 1].transpose();
    }
    M3 less = none;
    if (middle_ > 0) less += ne.chain_off[middle_ - 1].transpose() * link_[middle_ - 1];
    if (middle_ + 1 < n) less += ne.chain_off[middle_] * link_[middle_ + 1];
    if (!pivot(middle_, less)) return false;
    drifting_ = drifting;
    if (drifting) {
      Vec border(static_cast<Eigen::Index>(3 * n));
      for (size_t k = 0; k < n; ++k) border.segment<3>(static_cast<Eigen::Index>(3 * k)) = ne.chain_rate[k];
      u_.resize(border.size());
      solve_chain(border.data(), u_.data());
      const double s = ne.rate_rate + damping[static_cast<Eigen::Index>(3 * n)] - border.dot(u_);
      if (!(s > 0.0)) return false;
      schur_ = s;
    }
    return true;
  }

  // y = M⁻¹ r.
  void apply(const Vec& r, Vec& y) const {
    const Eigen::Index np = static_cast<Eigen::Index>(3 * inv_.size());
    solve_chain(r.data(), y.data());
    if (!drifting_) return;
    const double y_rate = (r[np] - u_.dot(r.head(np))) / schur_;
    y.head(np) -= u_ * y_rate;
    y[np] = y_rate;
  }

 private:
  // y = T⁻¹ r over the poses' 3n unknowns: forward from both ends to the middle, the
  // middle pose, back out to both ends; the two ends' steps interleaved.
  void solve_chain(const double* r, double* y) const {
    const size_t n = inv_.size();
    const size_t m = middle_;
    z_.resize(3 * n);
    double* z = z_.data();
    const auto copy = [&](size_t k) {
      z[3 * k] = r[3 * k];
      z[3 * k + 1] = r[3 * k + 1];
      z[3 * k + 2] = r[3 * k + 2];
    };
    // z_k = r_k - C_{k-1}ᵀ S_{k-1}⁻¹ z_{k-1} (top) and r_k - C_k P_{k+1}⁻¹ z_{k+1} (bottom).
    const size_t top = m, bottom = n - m - 1;  // poses above and below the middle
    for (size_t t = 0; t < std::max(top, bottom); ++t) {
      if (t < top) {
        copy(t);
        if (t > 0) sub_mtv(link_[t - 1], z + 3 * (t - 1), z + 3 * t);
      }
      if (t < bottom) {
        const size_t k = n - 1 - t;
        copy(k);
        if (t > 0) sub_mtv(link_[k + 1], z + 3 * (k + 1), z + 3 * k);
      }
    }
    copy(m);
    if (m > 0) sub_mtv(link_[m - 1], z + 3 * (m - 1), z + 3 * m);
    if (m + 1 < n) sub_mtv(link_[m + 1], z + 3 * (m + 1), z + 3 * m);
    const auto solve = [&](size_t k) {
      double* o = y + 3 * k;
      o[0] = o[1] = o[2] = 0.0;
      add_mv(inv_[k], z + 3 * k, o);
    };
    solve(m);
    // y_k = S_k⁻¹ z_k - link_k y_{k+1} (top), P_k⁻¹ z_k - link_k y_{k-1} (bottom).
    for (size_t t = 0; t < std::max(top, bottom); ++t) {
      if (t < top) {
        const size_t k = m - 1 - t;
        solve(k);
        sub_mv(link_[k], y + 3 * (k + 1), y + 3 * k);
      }
      if (t < bottom) {
        const size_t k = m + 1 + t;
        solve(k);
        sub_mv(link_[k], y + 3 * (k - 1), y + 3 * k);
      }
    }
  }

  size_t middle_ = 0;
  std::vector<M3> inv_;   // the pivot blocks' inverses: S_k⁻¹, P_k⁻¹, Σ⁻¹
  std::vector<M3> link_;  // S_k⁻¹ C_k above the middle, P_k⁻¹ C_{k-1}ᵀ below it
  bool drifting_ = false;
  mutable std::vector<double> z_;  // forward substitution's work space
  Vec u_;                 // T⁻¹ b, b the border
  double schur_ = 1.0;    // c - bᵀ T⁻¹ b
};

// (H + D) dx = rhs by Eigen's sparse LDLT: the fallback, and the reference in the tests.
bool solve_direct(const Problem& p, const Normal& ne, const Vec& damping, const Vec& rhs, Vec& dx) {
  const size_t n = ne.diag.size();
  const Eigen::Index dim = rhs.size();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(9 * (3 * n + 2 * p.edges.size()) + 7 * n);
  for (size_t k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        t.emplace_back(static_cast<int>(3 * k) + i, static_cast<int>(3 * k) + j,
                       ne.diag[k](i, j) + (i == j ? damping[static_cast<Eigen::Index>(3 * k) + i] : 0.0));
  const auto coupling = [&t](int a, int b, const M3& B) {  // H_ab = B and H_ba = Bᵀ
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        t.emplace_back(a + i, b + j, B(i, j));
        t.emplace_back(b + j, a + i, B(i, j));
      }
  };
  for (size_t k = 0; k + 1 < n; ++k) coupling(static_cast<int>(3 * k), static_cast<int>(3 * k + 3), ne.chain_off[k]);
  for (size_t e = 0; e < ne.ends.size(); ++e) coupling(ne.ends[e][0], ne.ends[e][1], ne.off[e]);
  if (p.drifting) {
    const int r = static_cast<int>(3 * n);
    for (size_t k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i) {
        t.emplace_back(static_cast<int>(3 * k) + i, r, ne.pose_rate[k][i]);
        t.emplace_back(r, static_cast<int>(3 * k) + i, ne.pose_rate[k][i]);
      }
    t.emplace_back(r, r, ne.rate_rate + damping[r]);
  }
  Eigen::SparseMatrix<double> H(dim, dim);
  H.setFromTriplets(t.begin(), t.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
  if (ldlt.info() != Eigen::Success) return false;
  dx = ldlt.solve(rhs);
  return ldlt.info() == Eigen::Success && dx.allFinite();
}

// A solve's buffers, kept by each thread from one solve to the next: at 5,000 keyframes
// they are about 3 MB, and touching that much fresh memory on every solve cost more page
// faults than the conjugate gradients' arithmetic. Values never carry from one solve to the
// next (every buffer is written before it is read).
struct Workspace {
  Normal ne;
  ChainPreconditioner M;
  Vec rhs, damping, zero, dx, r, z, q, d, Hdx;
  State trial;
};

// Preconditioned conjugate gradients from dx = 0. False when the tolerance is not reached.
bool solve_pcg(const Operator& H, Workspace& w, const PoseGraphConfig& config, int& iterations) {
  const Vec& rhs = w.rhs;
  const ChainPreconditioner& M = w.M;
  Vec& dx = w.dx;
  Vec& r = w.r;
  Vec& z = w.z;
  Vec& q = w.q;
  Vec& d = w.d;
  dx.setZero(rhs.size());
  r = rhs;
  z.resize(rhs.size());
  q.resize(rhs.size());
  M.apply(r, z);
  d = z;
  double rz = r.dot(z);
  const double stop = rz * config.pcg_tolerance * config.pcg_tolerance;
  if (rz <= 0.0) return rz == 0.0;
  for (int it = 0; it < config.pcg_max_iterations; ++it) {
    H.apply(d, q);
    const double dq = d.dot(q);
    if (!(dq > 0.0)) return false;
    const double alpha = rz / dq;
    dx += alpha * d;
    r -= alpha * q;
    M.apply(r, z);
    const double rz_next = r.dot(z);
    ++iterations;
    if (!std::isfinite(rz_next)) return false;
    if (rz_next <= stop) return true;
    d = z + (rz_next / rz) * d;
    rz = rz_next;
  }
  return false;
}

}  // namespace

PoseGraphSummary solve_pose_graph_pcg(std::vector<SE2>& poses, const SE2& prior,
                                      const Eigen::Vector3d& prior_sigma,
                                      const std::vector<GraphEdge>& edges,
                                      const PoseGraphConfig& config, HeadingDrift* drift) {
  PoseGraphSummary out;
  if (poses.empty()) return out;
  const size_t n = poses.size();
  Problem p{prior, prior_sigma, edges, false, 0.0, {}, {}};
  p.drifting = drift != nullptr && drift->prior_sigma_rad_s > 0.0;
  p.rate_sigma = p.drifting ? drift->prior_sigma_rad_s : 0.0;
  p.z_trig.resize(edges.size());
  p.mixed.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    p.z_trig[i] = {std::cos(edges[i].T_from_to.theta), std::sin(edges[i].T_from_to.theta)};
    p.mixed[i] = edges[i].mix.isIdentity(0.0) ? 0 : 1;
  }
  State x;
  x.pose.resize(n);
  for (size_t i = 0; i < n; ++i) x.pose[i] = V3(poses[i].x, poses[i].y, poses[i].theta);
  x.rate = p.drifting ? drift->rate_rad_s : 0.0;
  refresh_trig(x);
  const Eigen::Index np = static_cast<Eigen::Index>(3 * n);
  const Eigen::Index dim = np + (p.drifting ? 1 : 0);

  // Levenberg-Marquardt as Ceres runs it (trust region radius μ, damping diag(H)/μ clamped
  // to [1e-6, 1e32], step accepted when the actual decrease is over 1e-3 of the model's), so
  // the two solvers stop on the same criteria.
  double current = cost(p, x);
  out.initial_cost = current;
  out.iterations = 1;
  if (!std::isfinite(current)) return out;
  double radius = config.initial_trust_region_radius;
  double decrease_factor = 2.0;
  thread_local Workspace w;
  Normal& ne = w.ne;
  normal_equations(p, x, ne);
  bool converged = false;
  for (int step = 0; step < config.max_iterations && !converged; ++step) {
    Vec& rhs = w.rhs;
    rhs.resize(dim);
    double g_max = 0.0;
    for (size_t k = 0; k < n; ++k) {
      rhs.segment<3>(static_cast<Eigen::Index>(3 * k)) = -ne.g[k];
      g_max = std::max(g_max, ne.g[k].cwiseAbs().maxCoeff());
    }
    if (p.drifting) {
      rhs[np] = -ne.g_rate;
      g_max = std::max(g_max, std::abs(ne.g_rate));
    }
    if (g_max <= config.gradient_tolerance) break;  // already at the optimum
    Vec& damping = w.damping;
    damping.resize(dim);
    for (size_t k = 0; k < n; ++k)
      for (int i = 0; i < 3; ++i)
        damping[static_cast<Eigen::Index>(3 * k) + i] = std::clamp(ne.diag[k](i, i), 1e-6, 1e32) / radius;
    if (p.drifting) damping[np] = std::clamp(ne.rate_rate, 1e-6, 1e32) / radius;

    Vec& dx = w.dx;
    const Operator H{p, ne, damping};
    bool solved = w.M.factorise(ne, damping, p.drifting) && solve_pcg(H, w, config, out.linear_iterations);
    if (!solved) {
      ++out.direct_fallbacks;
      solved = solve_direct(p, ne, damping, rhs, dx);
    }
    ++out.iterations;
    if (!solved) break;

    // The model's decrease, without the damping (Ceres' model_cost_change): -(gᵀdx + ½dxᵀHdx).
    w.zero.setZero(dim);
    w.Hdx.resize(dim);
    Operator{p, ne, w.zero}.apply(dx, w.Hdx);
    const double model = -(-rhs.dot(dx) + 0.5 * dx.dot(w.Hdx));
    State& trial = w.trial;
    trial = x;
    for (size_t k = 0; k < n; ++k) trial.pose[k] += dx.segment<3>(static_cast<Eigen::Index>(3 * k));
    if (p.drifting) trial.rate += dx[np];
    refresh_trig(trial);
    const double next = cost(p, trial);
    const double rho = model > 0.0 ? (current - next) / model : -1.0;
    if (std::isfinite(next) && rho > 1e-3) {
      const double change = current - next;
      std::swap(x, trial);
      current = next;
      radius = radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      radius = std::min(radius, 1e16);
      decrease_factor = 2.0;
      if (config.model_agreement_stop > 0.0 && std::abs(1.0 - rho) < config.model_agreement_stop) converged = true;
      if (change <= config.function_tolerance * (current + change)) converged = true;
      double x_norm = 0.0;
      for (const V3& v : x.pose) x_norm += v.squaredNorm();
      if (dx.norm() <= config.parameter_tolerance * (std::sqrt(x_norm) + config.parameter_tolerance)) converged = true;
      if (!converged) normal_equations(p, x, ne);
    } else {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      if (radius < 1e-32) break;
    }
  }
  out.usable = std::isfinite(current);
  out.final_cost = current;
  if (out.usable) {
    for (size_t i = 0; i < n; ++i) poses[i] = {x.pose[i][0], x.pose[i][1], wrap_angle(x.pose[i][2])};
    if (p.drifting) drift->rate_rad_s = x.rate;
  }
  return out;
}

}  // namespace orthosonar::slam
