// Properties of the SLAM stages: ICP recovers known transforms (both directions) on scans
// that pin them down and never worsens the fit on any scan, the exact maximum clique equals
// brute force, PCM keeps exactly the consistent loop closures.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

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

TEST_CASE("PCM keeps exactly the consistent loop closures", "[property]") {
  rc::prop("pcm", [] {
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
        // Outliers: far off, each by its own offset and rotation, so no two agree either.
        const int o = k - n_good;
        const double a = 2.0 * 3.14159265 * o / 4.0;
        z = SE2{10.0 * std::cos(a), 10.0 * std::sin(a), 0.6 * (o + 1)} * z;
      }
      cands.push_back({from, to, {z, icp}});
      good.push_back(k < n_good);
    }
    // Shuffle deterministically so outliers are not always last.
    for (size_t i = cands.size(); i > 1; --i) {
      const size_t j = rng.below(i);
      std::swap(cands[i - 1], cands[j]);
      std::vector<bool>::swap(good[i - 1], good[j]);
    }
    const auto clique = maximum_clique(pcm_consistency(cands, odometry, 11.34));
    std::vector<int> expect;
    for (size_t i = 0; i < good.size(); ++i) {
      if (good[i]) expect.push_back(static_cast<int>(i));
    }
    RC_ASSERT(clique == expect);
  });
}
