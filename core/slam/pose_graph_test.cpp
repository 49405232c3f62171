#include "core/slam/pose_graph.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>

#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

namespace {

using Fn = std::function<Eigen::Vector3d(const std::vector<Eigen::Vector3d>&)>;

// Central differences of a residual with respect to block `which`.
Eigen::Matrix3d numeric_jacobian(const Fn& f, std::vector<Eigen::Vector3d> x, size_t which) {
  Eigen::Matrix3d J;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    auto xp = x, xm = x;
    xp[which][k] += h;
    xm[which][k] -= h;
    J.col(k) = (f(xp) - f(xm)) / (2 * h);
  }
  return J;
}

// A square of 4 sides of 10 m whose odometry turns 95 degrees instead of 90, and a loop
// closure saying the last pose is the first. Poses: the odometry chained from the origin.
std::pair<std::vector<GraphEdge>, std::vector<SE2>> drifting_square() {
  const double q = 1.5707963267948966;
  std::vector<GraphEdge> edges;
  std::vector<SE2> poses{{0, 0, 0}};
  for (int i = 0; i < 4; ++i) {
    const SE2 step{10, 0, q + 0.087};
    edges.push_back({i, i + 1, step, {0.2, 0.2, 0.02}});
    poses.push_back(poses.back() * step);
  }
  edges.push_back({0, 4, SE2{0, 0, 0}, {0.1, 0.1, 0.01}});
  return {edges, poses};
}

}  // namespace

TEST_CASE("Relative pose and prior Jacobians match numeric differentiation", "[unit]") {
  Rng rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const SE2 z{rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3)};
    const Eigen::Vector3d sigma(rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3), rng.uniform(0.005, 0.05));
    // Angles kept away from the wrap discontinuity of the residual.
    const Eigen::Vector3d a(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-3, 3));
    Eigen::Vector3d b(rng.uniform(-20, 20), rng.uniform(-20, 20), 0.0);
    b[2] = a[2] + z.theta + rng.uniform(-1, 1);
    const Fn rel = [&](const std::vector<Eigen::Vector3d>& x) {
      Eigen::Vector3d r;
      relative_pose_residual(x[0].data(), x[1].data(), z, sigma, r.data(), nullptr, nullptr);
      return r;
    };
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Ja, Jb;
    Eigen::Vector3d r;
    relative_pose_residual(a.data(), b.data(), z, sigma, r.data(), Ja.data(), Jb.data());
    CHECK((Eigen::Matrix3d(Ja) - numeric_jacobian(rel, {a, b}, 0)).cwiseAbs().maxCoeff() < 1e-5);
    CHECK((Eigen::Matrix3d(Jb) - numeric_jacobian(rel, {a, b}, 1)).cwiseAbs().maxCoeff() < 1e-5);

    Eigen::Vector3d near = a;
    near[2] = z.theta + rng.uniform(-1, 1);
    const Fn prior = [&](const std::vector<Eigen::Vector3d>& x) {
      Eigen::Vector3d rr;
      pose_prior_residual(x[0].data(), z, sigma, rr.data(), nullptr);
      return rr;
    };
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Jp;
    pose_prior_residual(near.data(), z, sigma, r.data(), Jp.data());
    CHECK((Eigen::Matrix3d(Jp) - numeric_jacobian(prior, {near}, 0)).cwiseAbs().maxCoeff() < 1e-5);
  }
}

TEST_CASE("Pose graph with a loop closure distributes a yaw drift", "[unit]") {
  auto [edges, poses] = drifting_square();
  const auto s = solve_pose_graph(poses, SE2{0, 0, 0}, {0.1, 0.1, 0.01}, edges, {});
  REQUIRE(s.usable);
  CHECK(s.final_cost < s.initial_cost);
  CHECK(std::hypot(poses[4].x, poses[4].y) < 0.3);
  CHECK(std::abs(wrap_angle(poses[4].theta)) < 0.05);
  // Deterministic: solving again from the same start gives bit-identical poses.
  auto again = drifting_square().second;
  (void)solve_pose_graph(again, SE2{0, 0, 0}, {0.1, 0.1, 0.01}, edges, {});
  for (size_t i = 0; i < poses.size(); ++i) {
    CHECK(again[i].x == poses[i].x);
    CHECK(again[i].theta == poses[i].theta);
  }
}

TEST_CASE("A leaf joined by two disagreeing edges: solving it alone equals re-solving the graph", "[unit]") {
  // The drifting square with its loop closure, solved; then a new pose joined to the last
  // one by two measurements of the same motion that disagree (a scan match and DR, one with
  // a weakened direction). Re-solving everything moves the other poses by no more than the
  // solver's tolerance (function_tolerance 1e-10 here: about 1e-6 m and 1e-7 rad), and the leaf lands where solve_leaf_pose puts it.
  PoseGraphConfig tight;
  tight.function_tolerance = 1e-10;
  tight.model_agreement_stop = 0.0;  // iterate to the tolerance, not to the first quadratic step
  auto [edges, poses] = drifting_square();
  REQUIRE(solve_pose_graph(poses, SE2{0, 0, 0}, {0.1, 0.1, 0.01}, edges, tight).usable);
  GraphEdge icp{4, 5, SE2{2.0, 0.3, 0.05}, {0.1, 0.1, 0.01}};
  icp.mix = Eigen::Vector3d(0.3, 1.0, 1.0).asDiagonal();
  edges.push_back(icp);
  edges.push_back({4, 5, SE2{2.2, 0.0, 0.02}, {0.05, 0.05, 0.005}});
  poses.push_back(poses[4] * icp.T_from_to);
  auto leaf = poses;
  auto full = poses;
  const auto ls = solve_leaf_pose(leaf, 5, edges, tight);
  REQUIRE(ls.usable);
  CHECK(ls.final_cost < ls.initial_cost);
  REQUIRE(solve_pose_graph(full, SE2{0, 0, 0}, {0.1, 0.1, 0.01}, edges, tight).usable);
  for (size_t i = 0; i < 5; ++i) {
    CHECK(leaf[i].x == poses[i].x);  // held exactly
    CHECK(std::abs(full[i].x - poses[i].x) < 1e-5);
    CHECK(std::abs(full[i].y - poses[i].y) < 1e-5);
    CHECK(std::abs(full[i].theta - poses[i].theta) < 1e-6);
  }
  const SE2 d = full[5].inverse() * leaf[5];
  CHECK(std::hypot(d.x, d.y) < 1e-5);
  CHECK(std::abs(d.theta) < 1e-6);
  // Between the two measurements, not at either.
  const SE2 rel = leaf[4].inverse() * leaf[5];
  CHECK(rel.x > 2.0 + 1e-3);
  CHECK(rel.x < 2.2 - 1e-3);
  // A pose no edge touches is left alone.
  auto lone = poses;
  CHECK_FALSE(solve_leaf_pose(lone, 3, {}, {}).usable);
  CHECK(lone[3].x == poses[3].x);
}

TEST_CASE("The drifting pose residual's Jacobians, the rate's included, match numeric differentiation", "[unit]") {
  Rng rng(12);
  for (int trial = 0; trial < 200; ++trial) {
    GraphEdge e{0, 1, SE2{rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3)},
                {rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3), rng.uniform(0.005, 0.05)}};
    e.dt_s = rng.uniform(0.5, 20.0);
    const double rate = rng.uniform(-0.01, 0.01);
    const Eigen::Vector3d a(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-3, 3));
    Eigen::Vector3d b(rng.uniform(-20, 20), rng.uniform(-20, 20), 0.0);
    b[2] = a[2] + e.T_from_to.theta + rng.uniform(-1, 1);
    // The rate rides along as the first coordinate of a third block.
    const Fn f = [&](const std::vector<Eigen::Vector3d>& x) {
      Eigen::Vector3d r;
      drifting_pose_residual(x[0].data(), x[1].data(), e, x[2][0], r.data(), nullptr, nullptr, nullptr);
      return r;
    };
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> Ja, Jb;
    Eigen::Vector3d r, Jr;
    drifting_pose_residual(a.data(), b.data(), e, rate, r.data(), Ja.data(), Jb.data(), Jr.data());
    const std::vector<Eigen::Vector3d> x{a, b, Eigen::Vector3d(rate, 0, 0)};
    CHECK((Eigen::Matrix3d(Ja) - numeric_jacobian(f, x, 0)).cwiseAbs().maxCoeff() < 1e-5);
    CHECK((Eigen::Matrix3d(Jb) - numeric_jacobian(f, x, 1)).cwiseAbs().maxCoeff() < 1e-5);
    CHECK((Jr - numeric_jacobian(f, x, 2).col(0)).cwiseAbs().maxCoeff() < 1e-4 * (1.0 + Jr.norm()));
    // No drift: the plain relative-pose residual.
    Eigen::Vector3d r0, r1;
    drifting_pose_residual(a.data(), b.data(), e, 0.0, r0.data(), nullptr, nullptr, nullptr);
    relative_pose_residual(a.data(), b.data(), e.T_from_to, e.sigma, r1.data(), nullptr, nullptr);
    CHECK(r0 == r1);
  }
}

TEST_CASE("A steady heading drift in the odometry is estimated against unbiased scan matches and a loop", "[unit]") {
  // Two laps of a 40 x 20 m rectangle, keyframes 4 s apart. DR's yaw increments carry a
  // drift of 0.01 deg/s; the scan matches are noisier in yaw but unbiased; a loop closure
  // joins each second-lap keyframe to the first lap's.
  const double rate = 0.01 * 3.14159265358979 / 180.0;
  const double dt = 4.0;
  std::vector<SE2> truth{{0, 0, 0}};
  const auto leg = [&](double length, int n) {
    for (int k = 0; k < n; ++k) truth.push_back(truth.back() * SE2{length / n, 0, k + 1 == n ? 1.5707963267948966 : 0.0});
  };
  for (int lap = 0; lap < 2; ++lap) {
    leg(40, 10);
    leg(20, 5);
    leg(40, 10);
    leg(20, 5);
  }
  Rng rng(5);
  std::vector<GraphEdge> edges;
  std::vector<SE2> dr{truth[0]};
  for (size_t k = 1; k < truth.size(); ++k) {
    const SE2 step = truth[k - 1].inverse() * truth[k];
    GraphEdge d{static_cast<int>(k - 1), static_cast<int>(k), step, {0.05, 0.05, 0.002}};
    d.T_from_to.theta += rate * dt + rng.normal() * 0.0005;
    d.dt_s = dt;
    edges.push_back(d);
    dr.push_back(dr.back() * d.T_from_to);
    GraphEdge m{static_cast<int>(k - 1), static_cast<int>(k), step, {0.1, 0.1, 0.01}};
    m.T_from_to.theta += rng.normal() * 0.005;
    edges.push_back(m);
  }
  for (int k = 30; k < static_cast<int>(truth.size()); ++k) edges.push_back({k - 30, k, SE2{0, 0, 0}, {0.3, 0.3, 0.02}});
  const auto heading_error = [&](const std::vector<SE2>& p) {
    double worst = 0.0;
    for (size_t k = 0; k < p.size(); ++k) worst = std::max(worst, std::abs(wrap_angle(p[k].theta - truth[k].theta)));
    return worst;
  };
  auto plain = dr;
  REQUIRE(solve_pose_graph(plain, truth[0], {0.01, 0.01, 0.001}, edges, {}).usable);
  auto drifting = dr;
  HeadingDrift drift{0.0, 0.05 * 3.14159265358979 / 180.0};
  REQUIRE(solve_pose_graph(drifting, truth[0], {0.01, 0.01, 0.001}, edges, {}, &drift).usable);
  INFO("rate " << drift.rate_rad_s << " (true " << rate << "), worst heading error plain "
               << heading_error(plain) << " drifting " << heading_error(drifting));
  CHECK(std::abs(drift.rate_rad_s - rate) < 0.2 * rate);
  CHECK(heading_error(drifting) < 0.5 * heading_error(plain));
  // The edges' dt is ignored without a drift prior: the plain solve again, bit for bit.
  auto off = dr;
  HeadingDrift none{0.0, 0.0};
  REQUIRE(solve_pose_graph(off, truth[0], {0.01, 0.01, 0.001}, edges, {}, &none).usable);
  CHECK(none.rate_rad_s == 0.0);
  for (size_t k = 0; k < off.size(); ++k) CHECK(off[k].theta == plain[k].theta);
}

TEST_CASE("A robust loss bounds the pull of a wrong loop closure and leaves correct ones alone", "[unit]") {
  // A 30-pose path of 1 m steps with a slight turn, exact odometry, four correct loop
  // closures across it and (optionally) one 3 m / 0.15 rad wrong one.
  std::vector<SE2> truth{{0, 0, 0}};
  std::vector<GraphEdge> edges;
  for (int i = 0; i < 29; ++i) {
    const SE2 step{1.0, 0.0, 0.1};
    edges.push_back({i, i + 1, step, {0.05, 0.05, 0.005}});
    truth.push_back(truth.back() * step);
  }
  for (int i : {0, 5, 10, 15}) edges.push_back({i, i + 14, truth[i].inverse() * truth[i + 14], {0.5, 0.5, 0.05}});
  const GraphEdge wrong{3, 25, SE2{3.0, 0.0, 0.15} * (truth[3].inverse() * truth[25]), {0.5, 0.5, 0.05}};
  const auto solve = [&](bool with_wrong, GraphEdge::Loss loss) {
    std::vector<GraphEdge> e = edges;
    if (with_wrong) e.push_back(wrong);
    for (size_t k = 29; k < e.size(); ++k) {  // the loop closures
      e[k].loss = loss;
      e[k].loss_scale = 3.37;
    }
    std::vector<SE2> poses(truth.size(), SE2{0, 0, 0});
    for (size_t k = 1; k < truth.size(); ++k) poses[k] = poses[k - 1] * edges[k - 1].T_from_to;  // odometry start
    const PoseGraphSummary s = solve_pose_graph(poses, truth[0], {0.01, 0.01, 0.001}, e, PoseGraphConfig{});
    REQUIRE(s.usable);
    double worst = 0.0;
    for (size_t k = 0; k < truth.size(); ++k)
      worst = std::max(worst, std::hypot(poses[k].x - truth[k].x, poses[k].y - truth[k].y));
    return worst;
  };
  const double clean_ls = solve(false, GraphEdge::Loss::kNone);
  const double clean_cauchy = solve(false, GraphEdge::Loss::kCauchy);
  const double bad_ls = solve(true, GraphEdge::Loss::kNone);
  const double bad_huber = solve(true, GraphEdge::Loss::kHuber);
  const double bad_cauchy = solve(true, GraphEdge::Loss::kCauchy);
  INFO("worst position error: correct loops " << clean_ls << " (Cauchy " << clean_cauchy << "); with a wrong loop "
       << bad_ls << ", Huber " << bad_huber << ", Cauchy " << bad_cauchy);
  CHECK(clean_ls < 1e-6);
  CHECK(clean_cauchy < 1e-6);  // residuals ~0: the loss changes nothing
  CHECK(bad_ls > 0.1);
  CHECK(bad_huber < bad_ls);  // convex: bounded pull, but a wrong loop still bends the path
  CHECK(bad_cauchy < 0.6 * bad_ls);

  // KeyframeSlam's form (one reweighting per re-solve): least squares with each loop's
  // residual scaled by sqrt(robust_weight) at the previous solution converges to the
  // Cauchy solution Ceres finds with the loss itself.
  std::vector<GraphEdge> e = edges;
  e.push_back(wrong);
  std::vector<SE2> poses(truth.size(), SE2{0, 0, 0});
  for (size_t k = 1; k < truth.size(); ++k) poses[k] = poses[k - 1] * edges[k - 1].T_from_to;
  std::vector<double> w(e.size(), 1.0);
  for (int step = 0; step < 30; ++step) {
    std::vector<GraphEdge> weighted = e;
    for (size_t k = 29; k < e.size(); ++k) {
      if (step > 0) w[k] = robust_weight(GraphEdge::Loss::kCauchy, 3.37, edge_whitened_norm(poses, e[k]));
      weighted[k].mix *= std::sqrt(w[k]);
    }
    REQUIRE(solve_pose_graph(poses, truth[0], {0.01, 0.01, 0.001}, weighted, PoseGraphConfig{}).usable);
  }
  double irls = 0.0;
  for (size_t k = 0; k < truth.size(); ++k) irls = std::max(irls, std::hypot(poses[k].x - truth[k].x, poses[k].y - truth[k].y));
  INFO("reweighted least squares: worst position error " << irls << ", wrong loop's weight " << w.back());
  CHECK(irls == Approx(bad_cauchy).margin(0.005));
  CHECK(w.back() < 0.5);
  CHECK(robust_weight(GraphEdge::Loss::kHuber, 2.0, 1.0) == 1.0);
  CHECK(robust_weight(GraphEdge::Loss::kHuber, 2.0, 4.0) == 0.5);
  CHECK(robust_weight(GraphEdge::Loss::kCauchy, 2.0, 2.0) == 0.5);
  CHECK(robust_weight(GraphEdge::Loss::kNone, 2.0, 9.0) == 1.0);
}
