#include "core/slam/pcm.hpp"

#include <catch2/catch.hpp>

#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

TEST_CASE("SE2 compounding covariance matches numeric Jacobians", "[unit]") {
  const SE2 a{1.0, -2.0, 0.7}, b{3.0, 0.5, -0.4};
  const auto f = [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
    const SE2 c = SE2{x[0], x[1], x[2]} * SE2{y[0], y[1], y[2]};
    return Eigen::Vector3d(c.x, c.y, c.theta);
  };
  const Eigen::Vector3d xa(a.x, a.y, a.theta), xb(b.x, b.y, b.theta);
  Eigen::Matrix3d J1, J2;
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    J1.col(k) = (f(xa + d, xb) - f(xa - d, xb)) / (2 * h);
    J2.col(k) = (f(xa, xb + d) - f(xa, xb - d)) / (2 * h);
  }
  Eigen::Matrix3d S1 = Eigen::Matrix3d::Identity() * 0.04, S2 = Eigen::Matrix3d::Identity() * 0.01;
  S1(2, 2) = 4e-4;
  const auto c = compose({a, S1}, {b, S2});
  const Eigen::Matrix3d expect = J1 * S1 * J1.transpose() + J2 * S2 * J2.transpose();
  CHECK((c.cov - expect).norm() < 1e-8);
  // Inverse: T * T^-1 = identity; covariance through the numeric Jacobian of inversion.
  Eigen::Matrix3d Ji;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[k] = h;
    const SE2 p = SE2{xa[0] + d[0], xa[1] + d[1], xa[2] + d[2]}.inverse();
    const SE2 m = SE2{xa[0] - d[0], xa[1] - d[1], xa[2] - d[2]}.inverse();
    Ji.col(k) = Eigen::Vector3d(p.x - m.x, p.y - m.y, p.theta - m.theta) / (2 * h);
  }
  CHECK((inverse({a, S1}).cov - Ji * S1 * Ji.transpose()).norm() < 1e-8);
}

TEST_CASE("Cycle error is zero for exact loop closures and large for a wrong one", "[unit]") {
  const SE2 a1{0, 0, 0}, a2{3, 0, 0.1}, b1{1, 8, 2.0}, b2{3.5, 8.2, 2.2};
  const Eigen::Matrix3d S = Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal();
  const UncertainSE2 z1{a1.inverse() * b1, S}, z2{a2.inverse() * b2, S};
  const UncertainSE2 bb{b1.inverse() * b2, S * 4}, aa{a2.inverse() * a1, S * 4};
  CHECK(cycle_mahalanobis2(z1, bb, z2, aa) < 1e-12);
  UncertainSE2 wrong = z2;
  wrong.T.x += 2.0;
  CHECK(cycle_mahalanobis2(z1, bb, wrong, aa) > 11.34);
}

TEST_CASE("Maximum clique of a known graph", "[unit]") {
  // 0-1-2 triangle, 2-3-4-5 4-clique, 6 isolated.
  Adjacency g(7, std::vector<bool>(7, false));
  const auto edge = [&](int a, int b) { g[a][b] = g[b][a] = true; };
  edge(0, 1), edge(1, 2), edge(0, 2);
  edge(2, 3), edge(2, 4), edge(2, 5), edge(3, 4), edge(3, 5), edge(4, 5);
  CHECK(maximum_clique(g) == std::vector<int>{2, 3, 4, 5});
  CHECK(maximum_clique_brute_force(g) == std::vector<int>{2, 3, 4, 5});
  CHECK(maximum_clique(Adjacency{}).empty());
  // Ties: two triangles, the lexicographically smaller wins.
  Adjacency t(6, std::vector<bool>(6, false));
  const auto e2 = [&](int a, int b) { t[a][b] = t[b][a] = true; };
  e2(3, 4), e2(4, 5), e2(3, 5), e2(0, 1), e2(1, 2), e2(0, 2);
  CHECK(maximum_clique(t) == std::vector<int>{0, 1, 2});
}
