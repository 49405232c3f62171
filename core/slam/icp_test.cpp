#include "core/slam/icp.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>

#include "core/random.hpp"
#include "core/slam/planar_cloud.hpp"
#include "core/slam/synthetic.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

TEST_CASE("ICP recovers a known SE2 transform of a scan", "[unit]") {
  const auto world = make_basin_world(7);
  const auto raw = synthetic_scan_V(world, {10.0, -20.0, 0.3}, {}, 1, 0);
  std::vector<Eigen::Vector2d> target;  // every 6th point: a sparse sample of the scan
  for (size_t i = 0; i < raw.size(); i += 6) target.push_back(raw[i]);
  const SE2 T{0.8, -0.5, 0.08};
  std::vector<Eigen::Vector2d> source;
  for (const auto& p : target) source.push_back(T.inverse() * p);  // T * source = target
  const auto r = icp_2d(source, target, SE2::identity(), {});
  REQUIRE(r.converged);
  CHECK(r.T_target_source.x == Approx(T.x).margin(1e-3));
  CHECK(r.T_target_source.y == Approx(T.y).margin(1e-3));
  CHECK(r.T_target_source.theta == Approx(T.theta).margin(1e-4));
  CHECK(r.rmse < 1e-6);
}

TEST_CASE("ICP with a fixed rotation solves for translation only, at the initial heading", "[unit]") {
  const auto world = make_basin_world(7);
  const auto raw = synthetic_scan_V(world, {10.0, -20.0, 0.3}, {}, 1, 0);
  std::vector<Eigen::Vector2d> target;
  for (size_t i = 0; i < raw.size(); i += 6) target.push_back(raw[i]);
  const SE2 T{0.8, -0.5, 0.08};
  std::vector<Eigen::Vector2d> source;
  for (const auto& p : target) source.push_back(T.inverse() * p);
  IcpConfig fixed;
  fixed.fix_rotation = true;
  // Started at the true heading: the translation is found exactly and the heading kept.
  const auto r = icp_2d(source, target, SE2{0.0, 0.0, T.theta}, fixed);
  REQUIRE(r.converged);
  CHECK(r.T_target_source.theta == T.theta);
  CHECK(r.T_target_source.x == Approx(T.x).margin(1e-3));
  CHECK(r.T_target_source.y == Approx(T.y).margin(1e-3));
  CHECK(r.rmse < 1e-6);
  // Started 0.02 rad off: the heading stays where it was put (the free fit would correct it).
  const auto off = icp_2d(source, target, SE2{0.0, 0.0, T.theta + 0.02}, fixed);
  CHECK(off.T_target_source.theta == T.theta + 0.02);
  const auto free_fit = icp_2d(source, target, SE2{0.0, 0.0, T.theta + 0.02}, {});
  CHECK(free_fit.T_target_source.theta == Approx(T.theta).margin(1e-4));
}

namespace {
// Points every `step` metres from `a` to `b`, the first `offset` metres in.
std::vector<Eigen::Vector2d> sampled_wall(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double step,
                                          double offset) {
  std::vector<Eigen::Vector2d> out;
  const double length = (b - a).norm();
  for (double s = offset; s <= length; s += step) out.push_back(a + (b - a) * (s / length));
  return out;
}
}  // namespace

TEST_CASE("Point-to-line ICP aligns walls sampled at other places along them", "[unit]") {
  // Two scans of one corner, each a 0.5 m sampling of the walls but offset by half a step
  // (two independent voxel grids): point-to-point ICP pairs each point with one a quarter of
  // a step along the wall, point-to-line with the wall itself.
  // (The walls stop 2 m short of their corner: a corner's neighbourhood is no line, and its
  // point-to-point rows would pair the offset samples again.)
  std::vector<Eigen::Vector2d> target = sampled_wall({2, 0}, {14, 0}, 0.5, 0.0);
  for (const auto& p : sampled_wall({0, 2}, {0, 10}, 0.5, 0.0)) target.push_back(p);
  std::vector<Eigen::Vector2d> seen = sampled_wall({2, 0}, {14, 0}, 0.5, 0.25);
  for (const auto& p : sampled_wall({0, 2}, {0, 10}, 0.5, 0.25)) seen.push_back(p);
  const SE2 T{0.3, -0.2, 0.035};  // 2 degrees
  std::vector<Eigen::Vector2d> source;
  for (const auto& p : seen) source.push_back(T.inverse() * p);
  IcpConfig line;
  line.metric = IcpConfig::Metric::kPointToLine;
  const auto r = icp_2d(source, target, SE2::identity(), line);
  const auto p2p = icp_2d(source, target, SE2::identity(), {});
  INFO("point-to-point: " << p2p.T_target_source.x << ", " << p2p.T_target_source.y << ", "
                          << p2p.T_target_source.theta << " rad; point-to-line: " << r.T_target_source.x << ", "
                          << r.T_target_source.y << ", " << r.T_target_source.theta << " rad");
  REQUIRE(r.converged);
  CHECK(r.T_target_source.x == Approx(T.x).margin(2e-3));
  CHECK(r.T_target_source.y == Approx(T.y).margin(2e-3));
  CHECK(r.T_target_source.theta == Approx(T.theta).margin(2e-4));
  CHECK(std::string(icp_metric_name(line.metric)) == "point_to_line");
}

TEST_CASE("Point-to-line ICP on one straight wall keeps the initial guess along it", "[unit]") {
  const std::vector<Eigen::Vector2d> target = sampled_wall({-10, 5}, {10, 5}, 0.5, 0.0);
  const SE2 T{0.0, 0.4, 0.02};  // the wall 0.4 m nearer and turned by 1.1 degrees
  std::vector<Eigen::Vector2d> source;
  for (const auto& p : sampled_wall({-8, 5}, {8, 5}, 0.5, 0.1)) source.push_back(T.inverse() * p);
  IcpConfig line;
  line.metric = IcpConfig::Metric::kPointToLine;
  const SE2 guess{0.3, 0.0, 0.0};  // 0.3 m off along the wall, which the wall cannot tell
  const auto r = icp_2d(source, target, guess, line);
  REQUIRE(r.converged);
  CHECK(r.T_target_source.theta == Approx(T.theta).margin(1e-4));
  // Across the wall the fit is exact: every source point lands on the target's line. Along
  // it the steps add nothing, and the fit stays where the guess put it.
  double worst = 0.0;
  for (const auto& p : source) worst = std::max(worst, std::abs((r.T_target_source * p).y() - 5.0));
  CHECK(worst < 1e-3);
  CHECK(r.T_target_source.x == Approx(guess.x).margin(0.05));
}

TEST_CASE("ICP reports failure without enough correspondences", "[unit]") {
  std::vector<Eigen::Vector2d> a{{0, 0}, {1, 0}}, b{{100, 100}};
  const auto r = icp_2d(a, b, SE2::identity(), {});
  CHECK_FALSE(r.converged);
  CHECK(r.inliers == 0);
  CHECK_FALSE(icp_2d({}, b, SE2::identity(), {}).converged);
}

// Both lookups: the dense cell table (points within a small box) and the sorted-entry
// search it falls back to (points spread over 1e6 m: a box of ~1e12 cells). Repeated
// points check the tie rule (the lowest index), `within` and `count_within` the radius.
TEST_CASE("Grid nearest neighbour and radius queries agree with brute force", "[unit]") {
  for (const double spread : {10.0, 1e6}) {
    CAPTURE(spread);
    Rng rng(3);
    std::vector<Eigen::Vector2d> pts;
    for (int i = 0; i < 500; ++i) pts.emplace_back(rng.uniform(-10, 10), rng.uniform(-10, 10));
    for (int i = 0; i < 20; ++i) pts.push_back(pts[static_cast<size_t>(i * 7)]);  // exact duplicates
    for (int i = 0; i < 30; ++i) pts.emplace_back(rng.uniform(-spread, spread), rng.uniform(-spread, spread));
    const Grid2d grid(pts, 1.5);
    for (int q = 0; q < 300; ++q) {
      const Eigen::Vector2d x = q % 5 == 0 ? pts[static_cast<size_t>(q)]
                                           : Eigen::Vector2d(rng.uniform(-12, 12), rng.uniform(-12, 12));
      long best = -1;
      double bd = 1.5 * 1.5;
      std::vector<long> near;
      for (size_t i = 0; i < pts.size(); ++i) {
        const double d = (pts[i] - x).squaredNorm();
        if (d < bd) {
          bd = d;
          best = static_cast<long>(i);
        }
        if (d <= 1.2 * 1.2) near.push_back(static_cast<long>(i));
      }
      double got_d2 = -1;
      CHECK(grid.nearest(x, 1.5, &got_d2) == best);
      if (best >= 0) CHECK(got_d2 == bd);
      CHECK(grid.within(x, 1.2) == near);
      CHECK(grid.count_within(x, 1.2) == near.size());
    }
    CHECK(grid.nearest({3 * spread, 0.0}, 1.5) == -1);  // outside every occupied cell
  }
  CHECK(Grid2d({}, 1.0).nearest({0, 0}, 5.0) == -1);
}

TEST_CASE("Voxel downsample keeps one centroid per voxel in sorted order", "[unit]") {
  const std::vector<Eigen::Vector2d> pts{{0.1, 0.1}, {0.3, 0.2}, {-0.2, 0.1}, {0.7, 0.1}, {0.2, 0.4}};
  const auto out = voxel_downsample(pts, 0.5);
  REQUIRE(out.size() == 3);
  CHECK(out[0].isApprox(Eigen::Vector2d(-0.2, 0.1)));
  CHECK(out[1].isApprox(Eigen::Vector2d(0.2, 0.7 / 3.0)));
  CHECK(out[2].isApprox(Eigen::Vector2d(0.7, 0.1)));
}

TEST_CASE("Radius outlier removal drops isolated points", "[unit]") {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < 6; ++i) pts.emplace_back(0.1 * i, 0.0);  // a tight cluster of 6
  pts.emplace_back(5.0, 5.0);                                   // isolated
  const auto out = remove_radius_outliers(pts, 1.0, 5);
  CHECK(out.size() == 6);
  CHECK(remove_radius_outliers(pts, 1.0, 6).empty());
}

namespace {

// Points every 0.5 m along the segment a -> b.
void add_segment(std::vector<Eigen::Vector2d>& out, Eigen::Vector2d a, Eigen::Vector2d b) {
  const int n = static_cast<int>(std::round((b - a).norm() / 0.5));
  for (int k = 0; k <= n; ++k) out.push_back(a + (b - a) * (static_cast<double>(k) / n));
}

}  // namespace

TEST_CASE("Fit information: one straight wall leaves translation along it unobserved", "[unit]") {
  std::vector<Eigen::Vector2d> wall;
  add_segment(wall, {-20.0, 8.0}, {20.0, 8.0});
  const FitInformation fit = icp_fit_information(wall, wall, SE2::identity());
  CHECK(fit.correspondences == wall.size());
  CHECK(fit.line_rows == wall.size());  // every neighbourhood is a line
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(fit.hessian);
  // The smallest eigenvalue is (numerically) zero, its direction pure x translation.
  CHECK(es.eigenvalues()(0) < 1e-9 * es.eigenvalues()(2));
  CHECK(std::abs(es.eigenvectors().col(0).x()) == Approx(1.0).margin(1e-6));
  // y and rotation are observed.
  CHECK(fit.hessian(1, 1) == Approx(static_cast<double>(wall.size())));
  CHECK(fit.hessian(2, 2) > 100.0);
}

TEST_CASE("Fit information: a corner or a row of isolated pilings observes every direction", "[unit]") {
  std::vector<Eigen::Vector2d> corner;
  add_segment(corner, {-20.0, 8.0}, {20.0, 8.0});
  add_segment(corner, {20.0, 8.0}, {20.0, -12.0});
  const FitInformation c = icp_fit_information(corner, corner, SE2{0.3, -0.2, 0.05});
  Eigen::Matrix3d Hc = c.hessian;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> ec(Eigen::Matrix2d(Hc.topLeftCorner<2, 2>()));
  CHECK(ec.eigenvalues()(0) > 0.3 * ec.eigenvalues()(1));  // 41 vs 81 rows per direction
  // Pilings 3 m apart along one line: isolated points, each constrains x and y.
  std::vector<Eigen::Vector2d> piles;
  for (int k = -5; k <= 5; ++k) piles.emplace_back(3.0 * k, 10.0);
  const FitInformation p = icp_fit_information(piles, piles, SE2::identity());
  CHECK(p.line_rows == 0);
  CHECK(p.hessian(0, 0) == Approx(11.0));
  CHECK(p.hessian(1, 1) == Approx(11.0));
}
