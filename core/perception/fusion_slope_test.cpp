// Fusion on sloped faces (issue 34; docs/PERCEPTION.md "Sloped faces"): an h return whose run
// along its beam is a sloped face filling the aperture takes its elevation from the run.
// Known answers on flat synthetic pairs.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/perception/fusion.hpp"
#include "core/perception/synthetic_pings.hpp"

using namespace orthosonar;
using namespace orthosonar::perception;
using orthosonar::perception::testing::flat_pair;
using orthosonar::perception::testing::nearest_col;
using orthosonar::perception::testing::set_pixel;

namespace {
constexpr double kSlopeDeg = std::numbers::pi / 180.0;
}  // namespace

TEST_CASE("sloped_face_elevation: the run's near end at -a, its far end at +a, linear between", "[unit]") {
  const double a = 10.0 * kSlopeDeg;
  CHECK(*sloped_face_elevation(20.0, 23.0, 20.0, a) == Approx(-a));
  CHECK(*sloped_face_elevation(20.0, 23.0, 23.0, a) == Approx(a));
  CHECK(*sloped_face_elevation(20.0, 23.0, 21.5, a) == Approx(0.0).margin(1e-12));
  CHECK(*sloped_face_elevation(20.0, 23.0, 22.25, a) == Approx(0.5 * a));
  CHECK(*sloped_face_elevation(20.0, 23.0, 30.0, a) == Approx(a));  // clamped to the run
  CHECK_FALSE(sloped_face_elevation(20.0, 20.0, 20.0, a).has_value());
  CHECK_FALSE(sloped_face_elevation(21.0, 20.0, 20.5, a).has_value());
}

TEST_CASE("slope_run_ratio: a return on a long run along its beam takes its elevation from the run", "[unit]") {
  // (slope_v_span_deg, the v image's check, is off until the last section.)
  // h: a run of 60 rows (3 m) in one beam at 4-7 m with a brighter return in its middle;
  // v: one return at the same range, 5 degrees up. A wall facing the sonar would give a run of
  // R (1/cos 10° - 1) = 0.09 m here, so this is a sloped face filling the aperture.
  auto hv = flat_pair();  // named, not a structured binding: the lambda below uses h and v
  SonarPing& h = hv.first;
  SonarPing& v = hv.second;
  const int col = 128, row = 110, near_row = 80, far_row = 140;
  const int col_v = nearest_col(v, 5.0 * kSlopeDeg);
  set_pixel(v, row, col_v, 250);
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;
  cfg.slope_run_floor = 0.2;  // the run (60) is above 0.2 x 250, the return
  cfg.slope_v_span_deg = 0.0;  // checked at the end
  auto fuse_with_run = [&](int r0, int r1) {
    SonarPing hh = h;
    for (int r = r0; r <= r1; ++r) set_pixel(hh, r, col, 60);
    set_pixel(hh, row, col, 250);
    return fuse_pair(hh, v, cfg);
  };
  const double a = cfg.overlap_deg * kSlopeDeg;
  const FusionResult slope = fuse_with_run(near_row, far_row);
  REQUIRE(slope.points.size() == 1);
  const FusedPoint& p = slope.points[0];
  CHECK(slope.sloped_face == 1);
  CHECK(p.elevation_from == FusedPoint::Elevation::sloped_face);
  CHECK(p.run_near_m == Approx(h.range_of_row(near_row)));
  CHECK(p.run_far_m == Approx(h.range_of_row(far_row)));
  const double expected = -a + 2.0 * a * (h.range_of_row(row) - h.range_of_row(near_row)) /
                                   (h.range_of_row(far_row) - h.range_of_row(near_row));
  CHECK(p.elevation_rad == Approx(expected).margin(1e-6));
  CHECK(std::abs(p.elevation_rad - v.bearings_rad[static_cast<size_t>(col_v)]) > 4.0 * kSlopeDeg);
  // Its σ is the run's, at its place along the run.
  CHECK(p.elevation_sigma_rad == Approx(elevation_sigma(cfg, FusedPoint::Elevation::sloped_face, 3.0, p.range_m,
                                                        expected, a)).epsilon(1e-5));
  // Its position is Eq. 1 at that elevation.
  const Vec3 q = cfg.T_V_h * spherical_to_cartesian(p.range_m, p.bearing_rad, expected);
  CHECK((p.p_V.cast<double>() - q).norm() < 1e-5);

  // Off: Eq. 6's elevation, the v return's.
  cfg.slope_run_ratio = 0.0;
  const FusionResult eq6 = fuse_with_run(near_row, far_row);
  REQUIRE(eq6.points.size() == 1);
  CHECK(eq6.sloped_face == 0);
  CHECK(eq6.points[0].elevation_from == FusedPoint::Elevation::v_return);
  CHECK(eq6.points[0].elevation_rad == Approx(v.bearings_rad[static_cast<size_t>(col_v)]));
  // Eq. 6 on a run some 30 walls long: the v return is one of many elevations the face spans
  // at this range, and its σ says so (far over mapping's default 2 degrees).
  CHECK(eq6.points[0].run_far_m - eq6.points[0].run_near_m == Approx(3.0).epsilon(1e-4));
  CHECK(eq6.points[0].elevation_sigma_rad > 5.0 * kSlopeDeg);

  // A run as short as a wall's (5 rows, 0.2 m < 8 x 0.09 m): Eq. 6's elevation.
  cfg.slope_run_ratio = 8.0;
  const FusionResult wall = fuse_with_run(row - 2, row + 2);
  REQUIRE(wall.points.size() == 1);
  CHECK(wall.sloped_face == 0);
  CHECK(wall.points[0].elevation_rad == Approx(v.bearings_rad[static_cast<size_t>(col_v)]));
  CHECK(wall.points[0].run_far_m - wall.points[0].run_near_m == Approx(4 * h.range_resolution_m));
  CHECK(wall.points[0].elevation_sigma_rad < 2.0 * kSlopeDeg);

  // Gaps of up to slope_run_max_gap rows are bridged; a wider one ends the run.
  SonarPing gapped = h;
  for (int r = near_row; r <= far_row; ++r) set_pixel(gapped, r, col, (r == 95 || r == 96) ? 5 : 60);
  set_pixel(gapped, row, col, 250);
  const FusionResult bridged = fuse_pair(gapped, v, cfg);
  REQUIRE(bridged.points.size() == 1);
  CHECK(bridged.points[0].run_near_m == Approx(h.range_of_row(near_row)));
  cfg.slope_run_max_gap = 1;
  const FusionResult cut = fuse_pair(gapped, v, cfg);
  REQUIRE(cut.points.size() == 1);
  CHECK(cut.points[0].run_near_m == Approx(h.range_of_row(97)));

  // slope_v_span_deg: the v image must see the face across its fan over the run's ranges.
  // With only the one v return (no span), Eq. 6; with v returns 8 degrees down near the run's
  // near end and 8 degrees up near its far end (16 degrees >= 10), the run's elevation.
  cfg.slope_run_max_gap = 2;
  cfg.slope_v_span_deg = 10.0;
  const FusionResult lone = fuse_with_run(near_row, far_row);
  REQUIRE(lone.points.size() == 1);
  CHECK(lone.sloped_face == 0);
  set_pixel(v, 100, nearest_col(v, -8.0 * kSlopeDeg), 250);
  set_pixel(v, 120, nearest_col(v, 8.0 * kSlopeDeg), 250);
  const FusionResult seen = fuse_with_run(near_row, far_row);
  REQUIRE(seen.points.size() == 1);
  CHECK(seen.sloped_face == 1);
  CHECK(seen.points[0].elevation_rad == Approx(expected).margin(1e-6));
}

TEST_CASE("slope_top_from_v: a run's elevation stays at or under the highest v detection over the run", "[unit]") {
  // h: the 3 m run of the test above with its bright return near the far end (row 130: 6.7
  // degrees up by the run); v: returns 8 degrees down at row 85, and the point's own return at
  // row 130, 3 degrees up. The face is seen no higher than 3 degrees over the run: the point is
  // clamped there. With a v return 8 degrees up at row 120, or the option off, it keeps 6.7.
  auto hv = flat_pair();
  SonarPing& h = hv.first;
  SonarPing& v = hv.second;
  const int col = 128, row = 130, near_row = 80, far_row = 140;
  for (int r = near_row; r <= far_row; ++r) set_pixel(h, r, col, 60);
  set_pixel(h, row, col, 250);
  const int col_v = nearest_col(v, 3.0 * kSlopeDeg);
  set_pixel(v, row, col_v, 250);
  set_pixel(v, 85, nearest_col(v, -8.0 * kSlopeDeg), 250);
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;
  cfg.slope_run_floor = 0.2;
  const double a = cfg.overlap_deg * kSlopeDeg;
  const double linear = -a + 2.0 * a * (h.range_of_row(row) - h.range_of_row(near_row)) /
                                 (h.range_of_row(far_row) - h.range_of_row(near_row));
  REQUIRE(linear > 6.0 * kSlopeDeg);
  const FusionResult clamped = fuse_pair(h, v, cfg);
  REQUIRE(clamped.points.size() == 1);
  CHECK(clamped.sloped_face == 1);
  CHECK(clamped.points[0].elevation_rad == Approx(v.bearings_rad[static_cast<size_t>(col_v)]));
  cfg.slope_top_from_v = false;
  const FusionResult as_run = fuse_pair(h, v, cfg);
  REQUIRE(as_run.points.size() == 1);
  CHECK(as_run.points[0].elevation_rad == Approx(linear).margin(1e-6));
  cfg.slope_top_from_v = true;
  set_pixel(v, 120, nearest_col(v, 8.0 * kSlopeDeg), 250);
  const FusionResult higher = fuse_pair(h, v, cfg);
  REQUIRE(higher.points.size() == 1);
  CHECK(higher.points[0].elevation_rad == Approx(linear).margin(1e-6));
}

TEST_CASE("elevation_sigma: a v return's grows with its run in wall-lengths, a sloped face's along the aperture",
          "[unit]") {
  FusionConfig cfg;  // 0.8 deg + 0.3 deg per wall beyond the first; 0.3 deg at -a to 1.1 deg at +a
  const double a = 10.0 * kSlopeDeg, range = 20.0;
  const double wall = range * (1.0 / std::cos(a) - 1.0);  // 0.3085 m
  using E = FusedPoint::Elevation;
  CHECK(elevation_sigma(cfg, E::v_return, 0.0, range, 0.0, a) == Approx(0.8 * kSlopeDeg));  // no run measured
  CHECK(elevation_sigma(cfg, E::v_return, 0.5 * wall, range, 0.0, a) == Approx(0.8 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::v_return, wall, range, 0.0, a) == Approx(0.8 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::v_return, 3.0 * wall, range, 0.0, a) == Approx(1.4 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::v_return, 5.0 * wall, range, 0.0, a) == Approx(2.0 * kSlopeDeg));
  // The same run at twice the range is half as many walls.
  CHECK(elevation_sigma(cfg, E::v_return, 3.0 * wall, 2.0 * range, 0.0, a) == Approx(0.95 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::sloped_face, 3.0, range, -a, a) == Approx(0.3 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::sloped_face, 3.0, range, 0.0, a) == Approx(0.7 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::sloped_face, 3.0, range, a, a) == Approx(1.1 * kSlopeDeg));
  CHECK(elevation_sigma(cfg, E::sloped_face, 3.0, range, 2.0 * a, a) == Approx(1.1 * kSlopeDeg));  // clamped
  cfg.sigma_v_deg = 0.5;
  cfg.sigma_v_per_wall_deg = 0.0;
  CHECK(elevation_sigma(cfg, E::v_return, 9.0 * wall, range, 0.0, a) == Approx(0.5 * kSlopeDeg));
}
