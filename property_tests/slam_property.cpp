// Properties of the SLAM stages: ICP recovers known transforms (both directions) on scans
// that pin them down and never worsens the fit on any scan, the exact maximum clique equals
// brute force, PCM keeps exactly the maximum consistent set of loop closures (against a
// reference with numeric Jacobians and subset enumeration, outliers near the threshold).
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/LU>

#include "core/random.hpp"
#include "core/slam/icp.hpp"
#include "core/slam/pcm.hpp"
#include "core/slam/synthetic.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

namespace {

const SyntheticWorld& world() {
  static const SyntheticWorld w = make_basin_world(21);
  return w;
}

bool close(const SE2& a, const SE2& b, double tol_m, double tol_rad) {
  const SE2 d = a.inverse() * b;
  return std::hypot(d.x, d.y) < tol_m && std::abs(d.theta) < tol_rad;
}

// One ICP case: a random sample of a scan from a random place inside the basin (`cloud`),
// the same points moved by a known transform T (`moved`, T * moved = cloud), T within the
// basin ICP is used in: a dead-reckoning guess off by <= 0.5 m and 3 degrees.
struct IcpCase {
  std::vector<Eigen::Vector2d> cloud, moved;
  SE2 T;
};

IcpCase make_icp_case(uint64_t seed) {
  Rng rng(seed);
  IcpCase c;
  const SE2 view{rng.uniform(-25, 25), rng.uniform(-15, 15), rng.uniform(-3.1, 3.1)};
  // A random sample of the scan (a voxel grid copied onto itself would alias by whole cells).
  const auto raw = synthetic_scan_V(world(), view, {}, seed, 0);
  for (const auto& p : raw) {
    if (rng.uniform() * static_cast<double>(raw.size()) < 400.0) c.cloud.push_back(p);
  }
  c.T = SE2{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.05, 0.05)};
  for (const auto& p : c.cloud) c.moved.push_back(c.T.inverse() * p);
  return c;
}

// How firmly a scan pins down its own position: shift the scan by 0.5 m against itself in
// each of 72 directions and take the mean squared nearest-neighbour distance (capped at
// 0.5 m) in the direction that costs least. A scan along one straight wall can slide along
// it almost for free (about 0.04 m^2); corners, crossing walls and pilings make every
// direction cost (median 0.077 m^2 over the basin). Point-to-point ICP may settle in a
// local minimum along such a slide (docs/VERIFICATION.md): its convergence basin is not
// guaranteed there, so the recovery property below claims only scans above the threshold.
// Every failure found, also from twice the basin (1 m, 0.1 rad), scored below 0.058; about
// 13 % of the generated scans score below the threshold.
constexpr double kPinnedSlideCost = 0.06;  // m^2
double slide_cost(const std::vector<Eigen::Vector2d>& cloud) {
  constexpr double kShift = 0.5, kCap = 0.5;
  const Grid2d grid(cloud, kCap);
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 72; ++k) {
    const double a = k * std::numbers::pi / 36.0;
    const Eigen::Vector2d d(kShift * std::cos(a), kShift * std::sin(a));
    double sum = 0.0;
    for (const auto& p : cloud) {
      double d2 = kCap * kCap;
      if (grid.nearest(p + d, kCap, &d2) < 0) d2 = kCap * kCap;
      sum += d2;
    }
    best = std::min(best, sum / static_cast<double>(cloud.size()));
  }
  return best;
}

// ICP's objective, computed independently of icp.cpp: the sum of the trim_fraction smallest
// squared nearest-neighbour distances of the moved source, a point without a match within
// the gate costing the whole gate.
double trimmed_cost(const std::vector<Eigen::Vector2d>& source, const std::vector<Eigen::Vector2d>& target,
                    const SE2& X, const IcpConfig& cfg) {
  const Grid2d grid(target, cfg.max_correspondence_m);
  const double cap = cfg.max_correspondence_m * cfg.max_correspondence_m;
  std::vector<double> d2s;
  for (const auto& p : source) {
    double d2 = cap;
    if (grid.nearest(X * p, cfg.max_correspondence_m, &d2) < 0) d2 = cap;
    d2s.push_back(d2);
  }
  std::sort(d2s.begin(), d2s.end());
  const auto keep = static_cast<size_t>(std::floor(cfg.trim_fraction * static_cast<double>(source.size())));
  double sum = 0.0;
  for (size_t i = 0; i < keep; ++i) sum += d2s[i];
  return sum;
}

IcpConfig property_config() {
  IcpConfig cfg;
  cfg.max_iterations = 100;
  return cfg;
}

}  // namespace

// ICP is a local method: it recovers T from the dead-reckoning basin where the scan's
// geometry pins all three degrees of freedom. The unrestricted claim was falsified by a
// random seed (a scan along one wall, docs/VERIFICATION.md); see the next property for what
// holds on every scan.
TEST_CASE("ICP recovers a known SE2 transform forward and inverse on a scan that pins it", "[property]") {
  rc::prop("icp round trip", [] {
    const auto c = make_icp_case(*rc::gen::inRange<uint64_t>(0, 1u << 30));
    RC_PRE(c.cloud.size() >= 50u);
    RC_PRE(slide_cost(c.cloud) >= kPinnedSlideCost);
    const IcpConfig cfg = property_config();
    const auto fwd = icp_2d(c.moved, c.cloud, SE2::identity(), cfg);
    RC_ASSERT(fwd.converged);
    RC_ASSERT(close(fwd.T_target_source, c.T, 1e-3, 1e-4));
    const auto inv = icp_2d(c.cloud, c.moved, SE2::identity(), cfg);
    RC_ASSERT(inv.converged);
    RC_ASSERT(close(inv.T_target_source, c.T.inverse(), 1e-3, 1e-4));
  });
}

// What ICP guarantees on any scan, degenerate ones included: the true transform is a fixed
// point (started there, it stays there), and from the dead-reckoning guess it never ends at
// a worse fit than it started from (its trimmed cost does not rise).
TEST_CASE("ICP keeps the true transform and never worsens the fit on any scan", "[property]") {
  rc::prop("icp fixed point and descent", [] {
    const auto c = make_icp_case(*rc::gen::inRange<uint64_t>(0, 1u << 30));
    RC_PRE(c.cloud.size() >= 50u);
    const IcpConfig cfg = property_config();
    for (const bool forward : {true, false}) {
      const auto& src = forward ? c.moved : c.cloud;
      const auto& tgt = forward ? c.cloud : c.moved;
      const SE2 truth = forward ? c.T : c.T.inverse();
      const auto at_truth = icp_2d(src, tgt, truth, cfg);
      RC_ASSERT(at_truth.converged);
      RC_ASSERT(close(at_truth.T_target_source, truth, 1e-6, 1e-7));
      RC_ASSERT(at_truth.rmse < 1e-6);
      const auto from_guess = icp_2d(src, tgt, SE2::identity(), cfg);
      RC_ASSERT(from_guess.converged);
      const double before = trimmed_cost(src, tgt, SE2::identity(), cfg);
      const double after = trimmed_cost(src, tgt, from_guess.T_target_source, cfg);
      RC_ASSERT(after <= before);
    }
  });
}

// The counterexample a random seed found (docs/VERIFICATION.md): a scan along one quay wall
// with three pilings. The slide measure must flag it, so the recovery property excludes it
// for the reason it fails; the forward match recovers T, the inverse one slides 0.6 m along
// the wall into a local minimum that still fits better than the guess it started from.
TEST_CASE("ICP counterexample seed 168785181 is a sliding scan", "[property]") {
  const auto c = make_icp_case(168785181);
  REQUIRE(c.cloud.size() == 397);
  CHECK(slide_cost(c.cloud) < kPinnedSlideCost);
  const IcpConfig cfg = property_config();
  const auto fwd = icp_2d(c.moved, c.cloud, SE2::identity(), cfg);
  CHECK(fwd.converged);
  CHECK(close(fwd.T_target_source, c.T, 1e-3, 1e-4));
  const auto inv = icp_2d(c.cloud, c.moved, SE2::identity(), cfg);
  CHECK(inv.converged);
  CHECK(trimmed_cost(c.cloud, c.moved, inv.T_target_source, cfg) <=
        trimmed_cost(c.cloud, c.moved, SE2::identity(), cfg));
}

TEST_CASE("Maximum clique equals brute force on random graphs", "[property]") {
  rc::prop("clique", [] {
    const int n = *rc::gen::inRange(0, 13);
    const auto density = *rc::gen::inRange(0, 101);
    Rng rng(*rc::gen::inRange<uint64_t>(0, 1u << 30));
    Adjacency g(static_cast<size_t>(n), std::vector<bool>(static_cast<size_t>(n), false));
    for (int a = 0; a < n; ++a) {
      for (int b = a + 1; b < n; ++b) {
        g[a][b] = g[b][a] = rng.below(100) < static_cast<uint64_t>(density);
      }
    }
    const auto bk = maximum_clique(g);
    RC_ASSERT(bk == maximum_clique_brute_force(g));
    for (size_t i = 0; i < bk.size(); ++i) {
      for (size_t j = i + 1; j < bk.size(); ++j) RC_ASSERT(g[bk[i]][bk[j]]);
    }
  });
}

namespace {

// The PCM cycle a_i -> b_i -> b_j -> a_j -> a_i as a plain function of the four relative
// poses' (x, y, theta), for the reference below.
SE2 pcm_reference_cycle(const std::array<SE2, 4>& p) { return p[0] * p[1] * p[2].inverse() * p[3]; }

// The squared Mahalanobis norm of that cycle computed the slow obvious way: its first-order
// covariance from central-difference Jacobians of the whole cycle with respect to each
// input (not the closed-form compounding pcm.cpp chains), solved with a full-pivot LU.
double pcm_reference_mahalanobis2(const UncertainSE2& z_i, const UncertainSE2& T_bi_bj, const UncertainSE2& z_j,
                                  const UncertainSE2& T_aj_ai) {
  const std::array<SE2, 4> p = {z_i.T, T_bi_bj.T, z_j.T, T_aj_ai.T};
  const std::array<const Eigen::Matrix3d*, 4> cov = {&z_i.cov, &T_bi_bj.cov, &z_j.cov, &T_aj_ai.cov};
  const SE2 c = pcm_reference_cycle(p);
  Eigen::Matrix3d sigma = Eigen::Matrix3d::Zero();
  const double h = 1e-6;
  for (size_t k = 0; k < 4; ++k) {
    Eigen::Matrix3d J;
    for (int d = 0; d < 3; ++d) {
      std::array<SE2, 4> plus = p, minus = p;
      double* vp = d == 0 ? &plus[k].x : d == 1 ? &plus[k].y : &plus[k].theta;
      double* vm = d == 0 ? &minus[k].x : d == 1 ? &minus[k].y : &minus[k].theta;
      *vp += h;
      *vm -= h;
      const SE2 a = pcm_reference_cycle(plus), b = pcm_reference_cycle(minus);
      J.col(d) = Eigen::Vector3d(a.x - b.x, a.y - b.y, wrap_angle(a.theta - b.theta)) / (2.0 * h);
    }
    sigma += J * *cov[k] * J.transpose();
  }
  const Eigen::Vector3d e(c.x, c.y, wrap_angle(c.theta));
  return e.dot(sigma.fullPivLu().solve(e));
}

}  // namespace

// Outliers are drawn from 0 to 8 m and +-0.3 rad off, so many sit near the chi-square
// threshold (a cycle of ~40 odometry steps has a sigma of metres): the answer is not "the
// good ones" but the maximum clique of the consistency graph, which the reference builds
// from its own Mahalanobis norms and searches by enumerating every subset. The counters
// check that the draws do reach both sides of the threshold.
TEST_CASE("PCM keeps exactly the maximum consistent set, near-threshold outliers included", "[property]") {
  constexpr double kThreshold = 11.34;
  int outlier_accepted = 0, outlier_rejected = 0, near_threshold_pairs = 0;
  rc::prop("pcm", [&] {
    Rng rng(*rc::gen::inRange<uint64_t>(0, 1u << 30));
    const int n_good = *rc::gen::inRange(2, 6);
    const int n_bad = *rc::gen::inRange(0, 5);
    // A true trajectory of 60 poses with odometry sigmas; loop closures from late to early.
    std::vector<SE2> truth{{0, 0, 0}};
    for (int i = 1; i < 60; ++i) truth.push_back(truth.back() * SE2{1.0, 0.0, rng.uniform(-0.15, 0.15)});
    const Eigen::Matrix3d odo = Eigen::Vector3d(0.04, 0.04, 4e-4).asDiagonal();
    const Eigen::Matrix3d icp = Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal();
    const OdometryFn odometry = [&](int i, int j) {
      UncertainSE2 u{truth[static_cast<size_t>(i)].inverse() * truth[static_cast<size_t>(j)],
                     odo * std::abs(j - i)};
      return u;
    };
    std::vector<LoopCandidate> cands;
    std::vector<bool> good;
    for (int k = 0; k < n_good + n_bad; ++k) {
      const int to = 40 + static_cast<int>(rng.below(20));
      const int from = static_cast<int>(rng.below(20));
      SE2 z = truth[static_cast<size_t>(from)].inverse() * truth[static_cast<size_t>(to)];
      if (k < n_good) {
        z = z * SE2{0.05 * rng.normal(), 0.05 * rng.normal(), 0.005 * rng.normal()};
      } else {
        const double r = 8.0 * rng.uniform(0.0, 1.0), a = rng.uniform(-3.14159265, 3.14159265);
        z = SE2{r * std::cos(a), r * std::sin(a), rng.uniform(-0.3, 0.3)} * z;
      }
      cands.push_back({from, to, {z, icp}});
      good.push_back(k < n_good);
    }
    const size_t n = cands.size();
    Adjacency reference(n, std::vector<bool>(n, false));
    for (size_t a = 0; a < n; ++a) {
      for (size_t b = a + 1; b < n; ++b) {
        const double m2 = pcm_reference_mahalanobis2(cands[a].z, odometry(cands[a].to, cands[b].to), cands[b].z,
                                                     odometry(cands[b].from, cands[a].from));
        // Two first-order computations agree to ~1e-8 relative; a pair on the threshold
        // itself has no right answer.
        RC_PRE(std::abs(m2 - kThreshold) > 1e-5 * kThreshold);
        reference[a][b] = reference[b][a] = m2 < kThreshold;
        if (m2 > 0.5 * kThreshold && m2 < 2.0 * kThreshold) ++near_threshold_pairs;
      }
    }
    const Adjacency graph = pcm_consistency(cands, odometry, kThreshold);
    RC_ASSERT(graph == reference);
    const auto clique = maximum_clique(graph);
    const auto expect = maximum_clique_brute_force(reference);
    RC_ASSERT(clique == expect);
    for (size_t i = 0; i < n; ++i) {
      if (good[i]) continue;
      const bool kept = std::find(expect.begin(), expect.end(), static_cast<int>(i)) != expect.end();
      ++(kept ? outlier_accepted : outlier_rejected);
    }
  });
  INFO("outliers accepted " << outlier_accepted << ", rejected " << outlier_rejected << ", near-threshold pairs "
                            << near_threshold_pairs);
  CHECK(outlier_accepted > 0);
  CHECK(outlier_rejected > 0);
  CHECK(near_threshold_pairs > 0);
}
