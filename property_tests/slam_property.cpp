// Properties of the SLAM stages: ICP recovers known transforms (both directions), the
// exact maximum clique equals brute force, PCM keeps exactly the consistent loop closures.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <cmath>

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

}  // namespace

TEST_CASE("ICP recovers a known SE2 transform forward and inverse", "[property]") {
  rc::prop("icp round trip", [] {
    const auto seed = *rc::gen::inRange<uint64_t>(0, 1u << 30);
    Rng rng(seed);
    // A scan from a random place inside the basin, then moved by a known transform.
    const SE2 view{rng.uniform(-25, 25), rng.uniform(-15, 15), rng.uniform(-3.1, 3.1)};
    // A random sample of the scan (a voxel grid copied onto itself would alias by whole cells).
    const auto raw = synthetic_scan_V(world(), view, {}, seed, 0);
    std::vector<Eigen::Vector2d> cloud;
    for (const auto& p : raw) {
      if (rng.uniform() * static_cast<double>(raw.size()) < 400.0) cloud.push_back(p);
    }
    RC_PRE(cloud.size() >= 50u);
    // Within the basin ICP is used in: a dead-reckoning guess off by <= 0.5 m and 3 degrees.
    const SE2 T{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.05, 0.05)};
    std::vector<Eigen::Vector2d> moved;  // T * moved = cloud
    for (const auto& p : cloud) moved.push_back(T.inverse() * p);
    IcpConfig cfg;
    cfg.max_iterations = 100;
    const auto fwd = icp_2d(moved, cloud, SE2::identity(), cfg);
    RC_ASSERT(fwd.converged);
    RC_ASSERT(close(fwd.T_target_source, T, 1e-3, 1e-4));
    const auto inv = icp_2d(cloud, moved, SE2::identity(), cfg);
    RC_ASSERT(inv.converged);
    RC_ASSERT(close(inv.T_target_source, T.inverse(), 1e-3, 1e-4));
  });
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
