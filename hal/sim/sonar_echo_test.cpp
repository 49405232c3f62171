// Known-answer tests of the field profile's echo image (sonar_echo.cpp, the head tables):
// side lobes, multipath ghosts, Lambertian seabed, absorption and TVG, and the range
// footprint of an elevation stratum. The image's geometry is sonar_renderer_test.cpp's.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/geometry.hpp"
#include "hal/sim/primitives.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {
namespace {

SonarModelConfig field_config() {
  SonarModelConfig c;
  apply_profile(c, SonarProfile::kField);
  return c;
}

// The field profile's seabed without beam pattern, multipath, texture or relief: Lambert alone.
SonarModelConfig plain_seabed_config() {
  SonarModelConfig c = field_config();
  c.beam_pattern = false;
  c.surface_reflection = 0.0;
  c.seabed_texture = 0.0;
  c.seabed_relief_deg = 0.0;
  return c;
}

// A flat seabed `altitude` below the origin.
TriangleMesh flat_seabed(double altitude) {
  TriangleMesh m;
  MeshBuilder(m).box({0.0, 0.0, -altitude - 0.5}, {200.0, 200.0, 1.0}, 0.0, {1, SemanticClass::kSeafloor});
  return m;
}

double db(double ratio) { return 10.0 * std::log10(ratio); }

// The echo at (row, col).
float echo_at(const EchoImage& e, int row, int col) {
  return e.echo[static_cast<size_t>(row) * static_cast<size_t>(e.cols) + static_cast<size_t>(col)];
}

// How many beams have an echo in the fan's last range bin.
int beams_in_last_bin(const EchoImage& e) {
  int n = 0;
  for (int col = 0; col < e.cols; ++col) n += echo_at(e, e.rows - 1, col) > 0.0f ? 1 : 0;
  return n;
}

// Sum of a column's echo over rows [r0, r1).
double column_sum(const EchoImage& e, int col, int r0 = 0, int r1 = -1) {
  double s = 0.0;
  for (int r = r0; r < (r1 < 0 ? e.rows : r1); ++r) s += echo_at(e, r, col);
  return s;
}

}  // namespace

TEST_CASE("field profile: a thin pole's side lobes peak at the configured level in neighbouring beams", "[hal]") {
  for (const double sll : {-28.0, -20.0}) {
    SonarModelConfig c = field_config();
    c.surface_reflection = 0.0;
    c.side_lobe_db = sll;
    TriangleMesh m;  // a 2 cm square pole, 10 m ahead, on the axis: narrower than one beam
    MeshBuilder(m).box({10.0, 0.0, 0.0}, {0.02, 0.02, 20.0}, 0.0, {1, SemanticClass::kPiling});
    const SonarRenderer renderer(m, c, Resolution::kFull, 1);
    const EchoImage e = renderer.echo(SE3::Identity(), SonarMount::kHorizontal);
    int peak = 0;
    for (int col = 0; col < e.cols; ++col) if (column_sum(e, col) > column_sum(e, peak)) peak = col;
    const double main = column_sum(e, peak);
    REQUIRE(main > 0.0);
    // The first side lobe spans u in (1, 2), u = angle / (beam width / 0.6391).
    const double w = c.head_h.beam_width_deg * kRadPerDeg / 0.6391;
    double side = 0.0;
    int side_beams = 0;
    for (int col = 0; col < e.cols; ++col) {
      const double u = std::abs(e.bearings_rad[static_cast<size_t>(col)] - e.bearings_rad[static_cast<size_t>(peak)]) / w;
      if (u > 1.15 && u < 1.85) {
        side = std::max(side, column_sum(e, col));
        ++side_beams;
      }
    }
    CHECK(side_beams >= 6);  // both sides of the target
    INFO("side lobe " << db(side / main) << " dB, configured " << sll);
    CHECK(db(side / main) == Approx(sll).margin(1.0));
    // Between the main lobe and the side lobe (the first null) the echo dips below it.
    double null_level = 1e30;
    for (int col = 0; col < e.cols; ++col) {
      const double u = std::abs(e.bearings_rad[static_cast<size_t>(col)] - e.bearings_rad[static_cast<size_t>(peak)]) / w;
      if (u > 0.9 && u < 1.1) null_level = std::min(null_level, column_sum(e, col));
    }
    CHECK(null_level < side);
  }
}

TEST_CASE("field profile: a surface ghost appears at the predicted range", "[hal]") {
  SonarModelConfig c = field_config();
  c.beam_pattern = false;
  c.surface_reflection = 0.5;
  // Vertical sonar 4 m below the surface looking forward; a sphere 12 m ahead at its depth.
  // Mirror image 8 m above it: t' = sqrt(12^2 + 8^2); cross paths at (t + t') / 2, the
  // double bounce at t'.
  const double depth = 4.0, ahead = 12.0, radius = 0.25;
  TriangleMesh m;
  MeshBuilder(m).sphere({ahead, 0.0, -depth}, radius, 24, {3, SemanticClass::kOther});
  const SonarRenderer renderer(m, c, Resolution::kFull, 1);
  const SE3 T_W_S = se3_from_xyz_rpy(0.0, 0.0, -depth, std::numbers::pi / 2.0, 0.0, 0.0);
  const EchoImage e = renderer.echo(T_W_S, SonarMount::kVertical);
  const double t = ahead - radius, t2 = std::hypot(ahead - radius, 2.0 * depth);
  const double r_cross = 0.5 * (t + t2);
  auto energy_near = [&e](double range_m, double half_m, double min_elev, double max_elev) {
    double s = 0.0;
    for (int r = 0; r < e.rows; ++r) {
      const double rr = (r + 1) * e.range_resolution_m;
      if (std::abs(rr - range_m) > half_m) continue;
      for (int col = 0; col < e.cols; ++col) {
        const double el = e.bearings_rad[static_cast<size_t>(col)];
        if (el >= min_elev && el <= max_elev) s += echo_at(e, r, col);
      }
    }
    return s;
  };
  const double direct = energy_near(t, 0.2, -5 * kRadPerDeg, 5 * kRadPerDeg);
  const double elev_mirror = std::atan2(2.0 * depth, ahead);
  const double ghost_own = energy_near(r_cross, 0.2, -5 * kRadPerDeg, 5 * kRadPerDeg);
  const double ghost_up = energy_near(r_cross, 0.2, elev_mirror - 4 * kRadPerDeg, elev_mirror + 4 * kRadPerDeg);
  const double ghost_double = energy_near(t2, 0.2, elev_mirror - 4 * kRadPerDeg, elev_mirror + 4 * kRadPerDeg);
  REQUIRE(direct > 0.0);
  INFO("direct " << direct << " cross own " << ghost_own << " cross up " << ghost_up << " double " << ghost_double);
  // Both cross paths carry R = 0.5 of the direct echo (same aperture gain across the fan).
  CHECK(db(ghost_own / direct) == Approx(db(0.5)).margin(1.0));
  CHECK(db(ghost_up / direct) == Approx(db(0.5)).margin(1.0));
  CHECK(db(ghost_double / direct) == Approx(db(0.25)).margin(1.0));
  // Nothing between the echo and the ghost.
  CHECK(energy_near(0.5 * (t + r_cross), 0.1, -90 * kRadPerDeg, 90 * kRadPerDeg) == 0.0);
  // Off: no ghost.
  c.surface_reflection = 0.0;
  const SonarRenderer plain(m, c, Resolution::kFull, 1);
  const EchoImage e0 = plain.echo(T_W_S, SonarMount::kVertical);
  double far = 0.0;
  for (int r = static_cast<int>((t + 0.5) / e0.range_resolution_m); r < e0.rows; ++r)
    for (int col = 0; col < e0.cols; ++col) far += echo_at(e0, r, col);
  CHECK(far == 0.0);
}

TEST_CASE("field profile: seabed backscatter follows Lambert's law against incidence", "[hal]") {
  SonarModelConfig c = plain_seabed_config();
  const TriangleMesh m = flat_seabed(5.0);
  const SonarRenderer renderer(m, c, Resolution::kFull, 1);
  // Vertical sonar: its beams measure elevation, so each beam meets the seabed at one incidence.
  const EchoImage e = renderer.echo(se3_from_xyz_rpy(0, 0, 0, std::numbers::pi / 2.0, 0, 0), SonarMount::kVertical);
  int checked = 0;
  for (int col = 0; col < e.cols; ++col) {
    const double el = e.bearings_rad[static_cast<size_t>(col)];
    if (el > -15 * kRadPerDeg || el < -60 * kRadPerDeg) continue;  // the seabed within 30 m, away from the fan edge
    // cos(incidence) = sin(|elevation|) for a flat bottom; each beam's weights sum to 1.
    const double ci = std::sin(-el);
    const double expected = c.seabed_mu * ci * ci;
    CHECK(column_sum(e, col) == Approx(expected).epsilon(0.05));
    ++checked;
  }
  CHECK(checked > 100);
  // With texture on, the mean over many beams stays near the Lambert value (log-normal, mean 1).
  c.seabed_texture = 0.6;
  const SonarRenderer textured(m, c, Resolution::kFull, 1);
  const EchoImage t = textured.echo(se3_from_xyz_rpy(0, 0, 0, std::numbers::pi / 2.0, 0, 0), SonarMount::kVertical);
  double ratio = 0.0;
  int n = 0;
  for (int col = 0; col < t.cols; ++col) {
    const double el = t.bearings_rad[static_cast<size_t>(col)];
    if (el > -15 * kRadPerDeg || el < -60 * kRadPerDeg) continue;
    ratio += column_sum(t, col) / (c.seabed_mu * std::sin(-el) * std::sin(-el));
    ++n;
  }
  CHECK(ratio / n == Approx(1.0).epsilon(0.35));
}

TEST_CASE("field profile: echo loss with range is absorption plus spreading minus TVG", "[hal]") {
  SonarModelConfig c = field_config();
  const SonarRenderer renderer(TriangleMesh{}, c, Resolution::kFull, 1);
  for (const SonarMount mount : {SonarMount::kHorizontal, SonarMount::kVertical}) {
    const EchoImage e = renderer.echo(SE3::Identity(), mount);
    const SonarHead& head = mount == SonarMount::kHorizontal ? c.head_h : c.head_v;
    const double alpha = absorption_db_per_m(head.frequency_hz, c.water_temperature_c, c.salinity_ppt, c.water_ph, 0.0);
    CHECK(renderer.absorption_db_per_m(mount) == Approx(alpha));
    for (const double r : {2.0, 5.0, 20.0, 29.0}) {
      const int row = static_cast<int>(std::lround(r / e.range_resolution_m)) - 1;
      const double rr = (row + 1) * e.range_resolution_m, rref = c.tvg_reference_m;
      // dB relative to the reference range: -(spreading + two-way absorption) + TVG.
      const double spreading = -10.0 * c.spreading_exponent * std::log10(rr / rref);
      const double absorption = -2.0 * alpha * (rr - rref);
      const double tvg = 10.0 * c.tvg_exponent * std::log10(rr / rref) + c.tvg_absorption_fraction * 2.0 * alpha * (rr - rref);
      CHECK(db(e.row_signal[static_cast<size_t>(row)]) == Approx(spreading + absorption + tvg).margin(0.01));
      CHECK(db(e.row_noise[static_cast<size_t>(row)]) == Approx(tvg).margin(0.01));
    }
  }
  // Ainslie & McColm at 10 C, 35 ppt, pH 8, surface: 0.24 dB/m at 750 kHz, 0.54 at 1.2 MHz,
  // 1.54 at 2.1 MHz (the M1200d's 2.1 MHz mode only reaches 10 m).
  CHECK(absorption_db_per_m(750e3, 10, 35, 8, 0) == Approx(0.22).margin(0.05));
  CHECK(absorption_db_per_m(1.2e6, 10, 35, 8, 0) == Approx(0.50).margin(0.1));
  CHECK(absorption_db_per_m(2.1e6, 10, 35, 8, 0) == Approx(1.45).margin(0.3));
  CHECK(absorption_db_per_m(1.2e6, 10, 0, 8, 0) < absorption_db_per_m(1.2e6, 10, 35, 8, 0));
}

TEST_CASE("field profile: the same seed gives the same bytes, profiles differ", "[hal]") {
  const Scene scene = *builtin_scene("marina1", 1);
  const SE3 T = se3_from_xyz_rpy(-21, 7, -scene.vehicle_depth_m, 0, 0, std::numbers::pi / 2.0);
  for (const SonarProfile p : {SonarProfile::kClean, SonarProfile::kField}) {
    SonarModelConfig c;
    apply_profile(c, p);
    c.seafloor_depth_m = scene.seafloor_depth_m;
    const SonarRenderer a(scene.mesh, c, Resolution::kReduced, 7), b(scene.mesh, c, Resolution::kReduced, 7);
    for (const SonarMount mount : {SonarMount::kHorizontal, SonarMount::kVertical}) {
      CHECK(a.render(T, mount, Time::from_s(1), 3, true).ping.image == b.render(T, mount, Time::from_s(1), 3, true).ping.image);
    }
  }
  SonarModelConfig clean, field;
  apply_profile(clean, SonarProfile::kClean);
  apply_profile(field, SonarProfile::kField);
  const SonarRenderer rc(scene.mesh, clean, Resolution::kReduced, 7), rf(scene.mesh, field, Resolution::kReduced, 7);
  CHECK(rc.render(T, SonarMount::kVertical, Time::from_s(1), 3).ping.image != rf.render(T, SonarMount::kVertical, Time::from_s(1), 3).ping.image);
}

TEST_CASE("range footprint: a sloping seabed's echo fills its ranges and keeps its energy", "[hal]") {
  // The horizontal sonar pitched 30 deg down at 5 m altitude: its 20 deg aperture meets a
  // flat seabed from 7.8 m to 14.6 m, so 32 elevation rays of one beam are 32 point echoes
  // over ~140 bins. With the footprint each ray covers its stratum's ranges instead.
  SonarModelConfig c = plain_seabed_config();
  c.beam_samples = 1;
  const TriangleMesh m = flat_seabed(5.0);
  const SE3 T = se3_from_xyz_rpy(0, 0, 0, 0, 30 * kRadPerDeg, 0);
  const SonarRenderer points(m, c, Resolution::kFull, 1);
  c.range_footprint = true;
  const SonarRenderer footprint(m, c, Resolution::kFull, 1);
  const EchoImage a = points.echo(T, SonarMount::kHorizontal), b = footprint.echo(T, SonarMount::kHorizontal);
  // Per column: the bins between the first and last echo, and how many of them are empty.
  auto gaps = [](const EchoImage& e, int col, int& span) {
    int first = -1, last = -1, empty = 0;
    for (int r = 0; r < e.rows; ++r) {
      if (echo_at(e, r, col) > 0.0f) {
        if (first < 0) first = r;
        last = r;
      }
    }
    for (int r = first; first >= 0 && r <= last; ++r) {
      if (echo_at(e, r, col) == 0.0f) ++empty;
    }
    span = first < 0 ? 0 : last - first + 1;
    return empty;
  };
  int checked = 0, gaps_points = 0, gaps_footprint = 0;
  for (int col = 0; col < a.cols; ++col) {
    if (std::abs(a.bearings_rad[static_cast<size_t>(col)]) > 40 * kRadPerDeg) continue;
    const double sa = column_sum(a, col), sb = column_sum(b, col);
    REQUIRE(sa > 0.0);
    CHECK(sb == Approx(sa).epsilon(0.02));  // the same energy, spread over range
    int span_a = 0, span_b = 0;
    gaps_points += gaps(a, col, span_a);
    gaps_footprint += gaps(b, col, span_b);
    CHECK(span_a > 100);
    CHECK(span_b >= span_a);
    ++checked;
  }
  CHECK(checked > 200);
  CHECK(gaps_points > 50 * checked);  // point echoes leave most bins of the span empty
  // The footprints tile the span: the only gaps are where neighbouring strata's rays,
  // jittered across the beam width, meet the slope at slightly different ranges.
  INFO("empty bins inside the span: " << gaps_points << " point echoes, " << gaps_footprint << " footprints, " << checked << " beams");
  CHECK(gaps_footprint * 10 < checked);
}

TEST_CASE("range footprint: a stratum that reaches the horizon spreads its echo to the fan's range", "[hal]") {
  // 0.2 m above a flat seabed, level: the strata just below the horizon hit the seabed
  // within 30 m, but their upper bounds look above it, so their footprints have no far end.
  SonarModelConfig c = plain_seabed_config();
  c.beam_samples = 1;
  c.range_footprint = true;
  const SonarRenderer r(flat_seabed(0.2), c, Resolution::kFull, 1);
  const EchoImage e = r.echo(SE3::Identity(), SonarMount::kHorizontal);
  for (int col = 0; col < e.cols; ++col) {
    for (int row = 0; row < e.rows; ++row) {
      const float v = echo_at(e, row, col);
      if (!std::isfinite(v) || v < 0.0f) FAIL("echo " << v << " at row " << row << ", beam " << col);
    }
  }
  const int reach_end = beams_in_last_bin(e);
  // The stratum just below the horizon ([-0.625, 0] deg) is open-ended; its jittered ray
  // hits within 30 m when it is more than 0.38 deg down: in about 40 % of the beams.
  CHECK(reach_end > e.cols / 4);  // the open footprints run to the last bin
  // Without the footprint the same rays are point echoes short of the fan's end.
  c.range_footprint = false;
  const SonarRenderer points(flat_seabed(0.2), c, Resolution::kFull, 1);
  CHECK(beams_in_last_bin(points.echo(SE3::Identity(), SonarMount::kHorizontal)) < reach_end);
}

}  // namespace orthosonar::sim
