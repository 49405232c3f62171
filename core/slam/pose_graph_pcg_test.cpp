#include "core/slam/pose_graph_pcg.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>

#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

namespace {

// A route round a 40 x 20 m rectangle flown `laps` times, one pose every 2 m; odometry with
// a yaw bias and noise between consecutive poses (the chain), twice for some of them (a DR
// and a scan-match factor), and loop closures from each pose of a later lap to the pose of
// a random earlier lap at the same place (the fill that defeats a sparse Cholesky).
// `mixed`: some loops carry a residual mixing; `drift_dt`: the DR edges carry their
// duration for the heading-drift state.
struct Graph {
  std::vector<SE2> truth, start;
  std::vector<GraphEdge> edges;
};

Graph revisiting_graph(uint64_t seed, int laps, bool mixed, bool drift_dt) {
  Rng rng(seed);
  Graph g;
  std::vector<SE2> lap;
  for (double s = 0.0; s < 120.0; s += 2.0) {
    if (s < 40) lap.push_back({s, 0, 0});
    else if (s < 60) lap.push_back({40, s - 40, 1.5707963267948966});
    else if (s < 100) lap.push_back({100 - s, 20, 3.141592653589793});
    else lap.push_back({0, 120 - s, -1.5707963267948966});
  }
  const int per_lap = static_cast<int>(lap.size());
  for (int l = 0; l < laps; ++l)
    for (const SE2& p : lap) g.truth.push_back(p);
  const int n = static_cast<int>(g.truth.size());
  g.start.push_back(g.truth[0]);
  for (int k = 0; k + 1 < n; ++k) {
    const SE2 z = g.truth[static_cast<size_t>(k)].inverse() * g.truth[static_cast<size_t>(k + 1)];
    const SE2 noisy{z.x + rng.normal(0, 0.05), z.y + rng.normal(0, 0.05), z.theta + 0.0015 + rng.normal(0, 0.002)};
    GraphEdge e{k, k + 1, noisy, {0.1, 0.1, 0.01}};
    if (drift_dt) e.dt_s = 4.0;
    g.edges.push_back(e);
    g.start.push_back(g.start.back() * noisy);
    if (k % 3 == 0) g.edges.push_back({k, k + 1, z, {0.2, 0.2, 0.02}});
  }
  for (int k = per_lap; k < n; ++k) {
    const int earlier = static_cast<int>(rng.uniform(0.0, static_cast<double>(k / per_lap) - 1e-9));
    const int j = earlier * per_lap + k % per_lap;
    const SE2 z = g.truth[static_cast<size_t>(j)].inverse() * g.truth[static_cast<size_t>(k)];
    GraphEdge e{j, k, {z.x + rng.normal(0, 0.03), z.y + rng.normal(0, 0.03), z.theta + rng.normal(0, 0.005)}, {0.1, 0.1, 0.01}};
    if (mixed && k % 4 == 0) e.mix = Eigen::Matrix3d{{1.0, 0.0, 0.0}, {0.0, 0.05, 0.0}, {0.0, 0.3, 1.0}};
    g.edges.push_back(e);
  }
  return g;
}

double max_position_difference(const std::vector<SE2>& a, const std::vector<SE2>& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::hypot(a[i].x - b[i].x, a[i].y - b[i].y));
  return d;
}

double max_heading_difference(const std::vector<SE2>& a, const std::vector<SE2>& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(wrap_angle(a[i].theta - b[i].theta)));
  return d;
}

PoseGraphConfig with(PoseGraphConfig::LinearSolver s) {
  PoseGraphConfig c;
  c.linear_solver = s;
  return c;
}

}  // namespace

TEST_CASE("Chain-preconditioned CG solves revisiting graphs as the sparse Cholesky does", "[unit]") {
  for (const bool mixed : {false, true}) {
    for (const uint64_t seed : {3u, 17u, 40u}) {
      const Graph g = revisiting_graph(seed, 6, mixed, false);
      auto cg = g.start, ref = g.start;
      const auto a = solve_pose_graph(cg, g.truth[0], {0.01, 0.01, 0.001}, g.edges, with(PoseGraphConfig::LinearSolver::kChainPcg));
      const auto b = solve_pose_graph(ref, g.truth[0], {0.01, 0.01, 0.001}, g.edges, with(PoseGraphConfig::LinearSolver::kSparseCholesky));
      INFO("seed " << seed << " mixed " << mixed << " cg iterations " << a.linear_iterations);
      REQUIRE(a.usable);
      REQUIRE(b.usable);
      CHECK(a.direct_fallbacks == 0);
      CHECK(a.linear_iterations > 0);
      CHECK(a.iterations == b.iterations);
      CHECK(std::abs(a.final_cost - b.final_cost) <= 1e-7 * b.final_cost);
      CHECK(max_position_difference(cg, ref) < 1e-6);
      CHECK(max_heading_difference(cg, ref) < 1e-8);
      // And the solve did something: the loops tie every lap to the first, which keeps its
      // own DR drift, while the start has drifted over all the laps.
      CHECK(max_position_difference(g.start, g.truth) > 5.0);
      CHECK(max_position_difference(cg, g.truth) < 0.3 * max_position_difference(g.start, g.truth));
    }
  }
}

TEST_CASE("Chain-preconditioned CG estimates the heading drift rate as the sparse Cholesky does", "[unit]") {
  const Graph g = revisiting_graph(5, 5, false, true);
  HeadingDrift d_cg{0.0, 0.01}, d_ref{0.0, 0.01};
  auto cg = g.start, ref = g.start;
  REQUIRE(solve_pose_graph(cg, g.truth[0], {0.01, 0.01, 0.001}, g.edges, with(PoseGraphConfig::LinearSolver::kChainPcg), &d_cg).usable);
  REQUIRE(solve_pose_graph(ref, g.truth[0], {0.01, 0.01, 0.001}, g.edges, with(PoseGraphConfig::LinearSolver::kSparseCholesky), &d_ref).usable);
  // The odometry's yaw bias is 0.0015 rad per 4 s edge.
  CHECK(d_cg.rate_rad_s == Approx(0.000375).margin(1e-4));
  CHECK(std::abs(d_cg.rate_rad_s - d_ref.rate_rad_s) < 1e-10);
  CHECK(max_position_difference(cg, ref) < 1e-6);
}

TEST_CASE("A step CG does not finish is solved by sparse LDLT, to the same answer", "[unit]") {
  const Graph g = revisiting_graph(8, 4, true, false);
  PoseGraphConfig capped;
  capped.pcg_max_iterations = 2;
  auto a = g.start, b = g.start;
  const auto sa = solve_pose_graph(a, g.truth[0], {0.01, 0.01, 0.001}, g.edges, capped);
  const auto sb = solve_pose_graph(b, g.truth[0], {0.01, 0.01, 0.001}, g.edges, PoseGraphConfig{});
  REQUIRE(sa.usable);
  CHECK(sa.direct_fallbacks == sa.iterations - 1);
  CHECK(sb.direct_fallbacks == 0);
  CHECK(max_position_difference(a, b) < 1e-6);
}

TEST_CASE("Chain-preconditioned CG: the same graph gives the same bits, on any thread", "[unit]") {
  const Graph g = revisiting_graph(21, 5, true, false);
  const auto solve = [&g](std::vector<SE2>& out) {
    out = g.start;
    (void)solve_pose_graph(out, g.truth[0], {0.01, 0.01, 0.001}, g.edges, PoseGraphConfig{});
  };
  std::vector<SE2> first, second, t1, t2;
  solve(first);
  solve(second);
  std::thread a([&] { solve(t1); });
  std::thread b([&] { solve(t2); });
  a.join();
  b.join();
  for (const auto* other : {&second, &t1, &t2}) {
    REQUIRE(other->size() == first.size());
    for (size_t i = 0; i < first.size(); ++i) {
      CHECK(std::memcmp(&first[i], &(*other)[i], sizeof(SE2)) == 0);
    }
  }
}

TEST_CASE("Robust losses: the robust weight is the derivative of rho, and both solvers reach the same robust optimum", "[unit]") {
  for (const auto loss : {GraphEdge::Loss::kHuber, GraphEdge::Loss::kCauchy}) {
    for (const double s : {0.1, 0.9, 4.0, 30.0}) {
      const double h = 1e-6 * s;
      const double numeric = (loss_rho(loss, 1.5, s + h) - loss_rho(loss, 1.5, s - h)) / (2 * h);
      CHECK(robust_weight(loss, 1.5, std::sqrt(s)) == Approx(numeric).epsilon(1e-6));
    }
    CHECK(loss_rho(loss, 1.5, 1.0) == Approx(1.0).epsilon(0.3));
    CHECK(loss_rho(loss, 0.0, 7.0) == 7.0);  // no scale: least squares
  }
  Graph g = revisiting_graph(9, 4, false, false);
  // Two wrong loop closures, 4 m off.
  g.edges.push_back({3, 3 + 2 * 60, SE2{4.0, 0.0, 0.0}, {0.1, 0.1, 0.01}});
  g.edges.push_back({20, 20 + 60, SE2{0.0, -4.0, 0.2}, {0.1, 0.1, 0.01}});
  for (auto& e : g.edges) {
    if (e.to - e.from > 1) {
      e.loss = GraphEdge::Loss::kCauchy;
      e.loss_scale = 3.0;
    }
  }
  PoseGraphConfig tight;
  tight.model_agreement_stop = 0.0;
  tight.function_tolerance = 1e-14;
  tight.max_iterations = 200;
  auto cg = g.start, ref = g.start;
  tight.linear_solver = PoseGraphConfig::LinearSolver::kChainPcg;
  REQUIRE(solve_pose_graph(cg, g.truth[0], {0.01, 0.01, 0.001}, g.edges, tight).usable);
  tight.linear_solver = PoseGraphConfig::LinearSolver::kSparseCholesky;
  REQUIRE(solve_pose_graph(ref, g.truth[0], {0.01, 0.01, 0.001}, g.edges, tight).usable);
  CHECK(max_position_difference(cg, ref) < 1e-4);
  // The wrong loops were not fitted: their residuals stay far beyond the loss's scale.
  for (size_t k = g.edges.size() - 2; k < g.edges.size(); ++k) CHECK(edge_whitened_norm(cg, g.edges[k]) > 10.0);
}

TEST_CASE("The linear solvers' configuration names", "[unit]") {
  CHECK(std::string(linear_solver_name(PoseGraphConfig::LinearSolver::kChainPcg)) == "chain_pcg");
  CHECK(std::string(linear_solver_name(PoseGraphConfig::LinearSolver::kSparseCholesky)) == "sparse_cholesky");
  CHECK(PoseGraphConfig{}.linear_solver == PoseGraphConfig::LinearSolver::kChainPcg);
}

TEST_CASE("Chain-preconditioned CG on graphs of 1 to 9 poses, with and without a drift state", "[unit]") {
  Rng rng(77);
  for (int n = 1; n <= 9; ++n) {
    for (const bool drifting : {false, true}) {
      std::vector<SE2> start{{0.5, -0.2, 0.1}};
      std::vector<GraphEdge> edges;
      for (int k = 0; k + 1 < n; ++k) {
        const SE2 z{2.0 + rng.normal(0, 0.1), rng.normal(0, 0.1), 0.3 + rng.normal(0, 0.02)};
        GraphEdge e{k, k + 1, z, {0.1, 0.1, 0.01}};
        e.dt_s = 5.0;
        edges.push_back(e);
        start.push_back(start.back() * SE2{z.x + 0.2, z.y - 0.1, z.theta + 0.01});
      }
      for (int k = 3; k < n; ++k) edges.push_back({k - 3, k, SE2{0.5, 1.0, 0.9}, {0.2, 0.2, 0.02}});
      auto cg = start, ref = start;
      HeadingDrift d_cg{0.0, 0.001}, d_ref{0.0, 0.001};
      const auto a = solve_pose_graph(cg, SE2{0, 0, 0}, {0.01, 0.01, 0.001}, edges,
                                      with(PoseGraphConfig::LinearSolver::kChainPcg), drifting ? &d_cg : nullptr);
      const auto b = solve_pose_graph(ref, SE2{0, 0, 0}, {0.01, 0.01, 0.001}, edges,
                                      with(PoseGraphConfig::LinearSolver::kSparseCholesky), drifting ? &d_ref : nullptr);
      INFO(n << " poses, drifting " << drifting);
      REQUIRE(a.usable);
      REQUIRE(b.usable);
      CHECK(a.direct_fallbacks == 0);
      CHECK(max_position_difference(cg, ref) < 1e-7);
      CHECK(max_heading_difference(cg, ref) < 1e-9);
      CHECK(std::abs(d_cg.rate_rad_s - d_ref.rate_rad_s) < 1e-10);
      CHECK(std::hypot(cg[0].x, cg[0].y) < 1e-3);  // the prior holds pose 0
    }
  }
}
