// Fusion against constructions with a known answer: point targets at known (R, θ, φ)
// rendered into both polar images on a noise background.
#include <algorithm>
#include <catch2/catch.hpp>
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <cmath>
#include <numbers>

#include "core/perception/fusion.hpp"
#include "core/perception/synthetic_pings.hpp"
#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::perception;
using orthosonar::perception::testing::beam_width;
using orthosonar::perception::testing::draw_blob;
using orthosonar::perception::testing::nearest_col;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A reduced-resolution ping: 200 bins x 128 beams, exponential speckle of the given mean.
SonarPing noise_ping(SonarMount mount, uint64_t seed, double mean) {
  return testing::speckle_ping(mount, 200, 128, seed, mean);
}


struct Target {
  double range, theta, phi;
};

FusionResult render_and_fuse(const std::vector<Target>& targets, uint64_t seed,
                             const FusionConfig& cfg = {}) {
  SonarPing h = noise_ping(SonarMount::kHorizontal, derive_seed(seed, 1), 6.0);
  SonarPing v = noise_ping(SonarMount::kVertical, derive_seed(seed, 2), 6.0);
  for (const Target& t : targets) {
    draw_blob(h, t.range, t.theta, 230, 170);
    draw_blob(v, t.range, t.phi, 230, 170);
  }
  return fuse_pair(h, v, cfg);
}

// An h/v pair of 200 bins x 256 beams (±32°, uniform) on a flat background of 5.
std::pair<SonarPing, SonarPing> flat_pair() {
  SonarPing h, v;
  for (SonarPing* p : {&h, &v}) {
    p->rows = 200;
    p->cols = 256;
    p->range_resolution_m = 0.05;
    for (int c = 0; c < p->cols; ++c) p->bearings_rad.push_back((-32.0 + 64.0 * c / 255.0) * std::numbers::pi / 180.0);
    p->image.assign(static_cast<size_t>(p->rows) * p->cols, 5);
  }
  h.mount = SonarMount::kHorizontal;
  v.mount = SonarMount::kVertical;
  return {std::move(h), std::move(v)};
}

}  // namespace

TEST_CASE("A point target inside the overlap fuses within one bin and one beam", "[unit]") {
  const SonarPing ref = noise_ping(SonarMount::kHorizontal, 0, 1.0);
  for (const Target t : {Target{4.0, 3.0 * kDeg, -4.0 * kDeg}, Target{7.3, -8.0 * kDeg, 6.5 * kDeg},
                         Target{2.2, 0.0, 0.0}}) {
    const FusionResult r = render_and_fuse({t}, 11);
    INFO("target R " << t.range << " theta " << t.theta << " phi " << t.phi);
    REQUIRE_FALSE(r.points.empty());
    const double bw_theta = beam_width(ref, nearest_col(ref, t.theta));
    const double bw_phi = beam_width(ref, nearest_col(ref, t.phi));
    for (const FusedPoint& p : r.points) {
      CHECK(std::abs(p.range_m - t.range) <= 0.05 + 1e-6);
      CHECK(std::abs(p.bearing_rad - t.theta) <= 1.5 * bw_theta);
      CHECK(std::abs(p.elevation_rad - t.phi) <= 1.5 * bw_phi);
      // Eq. 1 in the h frame, then T_V_h (translation 0.35 m along x).
      const Vec3 want = default_T_V_h() * spherical_to_cartesian(p.range_m, p.bearing_rad, p.elevation_rad);
      CHECK((p.p_V.cast<double>() - want).norm() < 1e-5);
    }
    // The centre pixels pair with each other: a point at the blob centre exists.
    bool centre = false;
    for (const FusedPoint& p : r.points) {
      const Vec3 truth = default_T_V_h() * spherical_to_cartesian(t.range, t.theta, t.phi);
      centre |= (p.p_V.cast<double>() - truth).norm() < 0.05 + t.range * 0.5 * (bw_theta + bw_phi);
    }
    CHECK(centre);
  }
}

TEST_CASE("Targets outside the overlap give no point", "[unit]") {
  // Outside in θ (h sees it at 25°, v within), outside in φ, and outside in both.
  for (const Target t : {Target{5.0, 25.0 * kDeg, 2.0 * kDeg}, Target{5.0, -2.0 * kDeg, -20.0 * kDeg},
                         Target{6.0, 40.0 * kDeg, 30.0 * kDeg}}) {
    const FusionResult r = render_and_fuse({t}, 12);
    INFO("target R " << t.range << " theta " << t.theta << " phi " << t.phi);
    CHECK(r.points.empty());
    CHECK_FALSE(r.detections_h.empty());  // the target itself was detected
  }
}

TEST_CASE("Two targets at the same range are associated by patch cost", "[unit]") {
  // Same range bin: one subproblem with two candidates per side (per pixel row).
  // Target A is a full bright blob, target B a single bright pixel: the patches differ.
  SonarPing h = noise_ping(SonarMount::kHorizontal, 21, 6.0);
  SonarPing v = noise_ping(SonarMount::kVertical, 22, 6.0);
  draw_blob(h, 5.0, -6.0 * kDeg, 230, 200);
  draw_blob(v, 5.0, 5.0 * kDeg, 230, 200);
  draw_blob(h, 5.0, 6.0 * kDeg, 230, 0);
  draw_blob(v, 5.0, -5.0 * kDeg, 230, 0);
  const FusionResult r = fuse_pair(h, v, FusionConfig{});
  REQUIRE_FALSE(r.points.empty());
  const double tol = 1.5 * beam_width(h, nearest_col(h, 6.0 * kDeg));
  for (const FusedPoint& p : r.points) {
    // θ < 0 must come with φ > 0 and vice versa (never the swapped association).
    if (p.bearing_rad < 0) CHECK(std::abs(p.elevation_rad - 5.0 * kDeg) <= tol);
    if (p.bearing_rad > 0) CHECK(std::abs(p.elevation_rad + 5.0 * kDeg) <= tol);
  }
  CHECK(r.subproblems >= 1);
  CHECK(r.matches >= r.points.size());
  CHECK(r.matches == r.points.size() + r.culled_low_confidence);
}

TEST_CASE("Each point lists its range bin's v candidates, its own elevation among them", "[unit]") {
  // Two full blobs per image at one range: the bins at that range have both v candidates.
  SonarPing h = noise_ping(SonarMount::kHorizontal, 23, 6.0);
  SonarPing v = noise_ping(SonarMount::kVertical, 24, 6.0);
  draw_blob(h, 5.0, -6.0 * kDeg, 230, 200);
  draw_blob(h, 5.0, 6.0 * kDeg, 230, 200);
  draw_blob(v, 5.0, 5.0 * kDeg, 230, 200);
  draw_blob(v, 5.0, -5.0 * kDeg, 230, 200);
  FusionConfig keep_all;
  keep_all.min_confidence = -1.0;  // every match, however ambiguous
  const FusionResult r = fuse_pair(h, v, keep_all);
  REQUIRE_FALSE(r.points.empty());
  size_t with_both = 0;
  for (const FusedPoint& p : r.points) {
    REQUIRE(p.bin_count >= 1);
    REQUIRE(p.bin_first + p.bin_count <= r.bin_elevations_rad.size());
    const auto first = r.bin_elevations_rad.begin() + p.bin_first;
    CHECK(std::find(first, first + p.bin_count, p.elevation_rad) != first + p.bin_count);
    with_both += std::any_of(first, first + p.bin_count, [](float e) { return e > 0.0f; }) &&
                 std::any_of(first, first + p.bin_count, [](float e) { return e < 0.0f; });
  }
  CHECK(with_both >= 2);  // both h blobs chose between the two v blobs
}

TEST_CASE("Confidence threshold culls ambiguous matches", "[unit]") {
  FusionConfig strict;
  strict.min_confidence = 2.0;  // above any C with alternatives (C <= 1)
  const FusionResult r = render_and_fuse({Target{4.0, 3.0 * kDeg, -4.0 * kDeg}, Target{4.0, -3.0 * kDeg, 4.0 * kDeg}}, 31, strict);
  CHECK(r.matches > 0);
  for (const FusedPoint& p : r.points) CHECK(p.confidence == 1.0f);  // only the no-alternative ones
  CHECK(r.matches == r.points.size() + r.culled_low_confidence);
}

TEST_CASE("Planar points put horizontal detections at zero elevation in V", "[unit]") {
  SonarPing h = noise_ping(SonarMount::kHorizontal, 1, 1.0);
  const std::vector<Detection> dets = {{99, 64, 200.0f}};
  const auto pts = planar_points_V(h, dets, default_T_V_h());
  REQUIRE(pts.size() == 1);
  const double th = h.bearings_rad[64];
  CHECK(pts[0].x() == Approx(0.35 + 5.0 * std::cos(th)));
  CHECK(pts[0].y() == Approx(5.0 * std::sin(th)));
  const auto p3 = points_V_at_elevation(h, dets, default_T_V_h(), 0.1);
  REQUIRE(p3.size() == 1);
  CHECK(p3[0].z() == Approx(5.0 * std::sin(0.1)));
}

TEST_CASE("Default extrinsics: v is h rolled +90 degrees about x", "[unit]") {
  // A v beam at bearing φ (its own +y) points up in V.
  const Vec3 d = default_T_V_v().linear() * spherical_to_cartesian(1.0, 0.3, 0.0);
  CHECK(d.z() == Approx(std::sin(0.3)));
  CHECK(std::abs(d.y()) < 1e-12);
  CHECK(default_T_V_v().translation().z() == Approx(-0.10));
}

TEST_CASE("The overlap strip's CFAR equals the whole image's CFAR restricted to the overlap", "[unit]") {
  Rng rng(77);
  for (int trial = 0; trial < 40; ++trial) {
    SonarPing p;
    p.rows = static_cast<uint16_t>(20 + rng.below(200));
    p.cols = static_cast<uint16_t>(8 + rng.below(300));
    p.bytes_per_pixel = trial % 5 == 4 ? 2 : 1;
    const double half = (20.0 + 50.0 * rng.uniform()) * std::numbers::pi / 180.0;
    for (int c = 0; c < p.cols; ++c) p.bearings_rad.push_back(-half + 2.0 * half * c / (p.cols - 1));
    p.image.resize(static_cast<size_t>(p.rows) * p.cols * p.bytes_per_pixel);
    for (auto& x : p.image) x = static_cast<uint8_t>(rng.uniform() < 0.05 ? 200 + rng.below(56) : rng.below(90));
    CfarConfig cfg;
    cfg.window = trial % 2 ? CfarWindow::kCross : CfarWindow::kRange;
    cfg.method = trial % 3 == 0 ? CfarMethod::kCa : CfarMethod::kSoca;
    cfg.train_cells = 1 + static_cast<int>(rng.below(25));
    cfg.guard_cells = static_cast<int>(rng.below(6));
    cfg.gate = trial % 4 == 0 ? 0.0 : 65.0;
    cfg.min_neighbours = static_cast<int>(rng.below(4));
    const double lim = (2.0 + 25.0 * rng.uniform()) * std::numbers::pi / 180.0;
    std::vector<Detection> whole = cfar_detect(p, cfg);
    std::erase_if(whole, [&](const Detection& d) { return std::abs(p.bearings_rad[static_cast<size_t>(d.col)]) > lim; });
    const std::vector<Detection> strip = cfar_detect_within(p, cfg, lim);
    REQUIRE(strip.size() == whole.size());
    for (size_t i = 0; i < strip.size(); ++i) {
      CHECK(strip[i].row == whole[i].row);
      CHECK(strip[i].col == whole[i].col);
      CHECK(strip[i].intensity == whole[i].intensity);
    }
  }
}

TEST_CASE("peak_window_deg keeps one candidate per main lobe: a blurred target fuses at its peak beam", "[unit]") {
  // h: a target blurred over 7 beams at one range, brightest in the middle; v: one target.
  auto [h, v] = flat_pair();
  const int row = 120, mid = 128;
  const uint8_t blur[7] = {120, 160, 200, 250, 200, 160, 120};
  for (int k = 0; k < 7; ++k) h.image[static_cast<size_t>(row) * h.cols + static_cast<size_t>(mid - 3 + k)] = blur[k];
  v.image[static_cast<size_t>(row) * v.cols + static_cast<size_t>(mid)] = 250;
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;  // one-row targets
  cfg.peak_window_deg = 0.0;
  const FusionResult all = fuse_pair(h, v, cfg);
  cfg.peak_window_deg = 1.0;
  const FusionResult peak = fuse_pair(h, v, cfg);
  CHECK(all.candidates_h == 7);
  REQUIRE(peak.candidates_h == 1);
  REQUIRE(peak.points.size() == 1);
  CHECK(peak.points[0].bearing_rad == Approx(h.bearings_rad[static_cast<size_t>(mid)]));
}

TEST_CASE("noise_floor_factor drops candidates under the local noise floor (largest row median within ±rows)",
          "[unit]") {
  // Both images: background 5 in rows < 150 and 60 from row 150 on (a TVG-lifted far field).
  auto [h, v] = flat_pair();
  for (SonarPing* p : {&h, &v})
    for (size_t i = 150 * static_cast<size_t>(p->cols); i < p->image.size(); ++i) p->image[i] = 60;
  RowMedians med(h);
  CHECK(med(10) == 5.0);
  CHECK(med(150) == 60.0);
  CHECK(med.local_floor(144, 5) == 5.0);
  CHECK(med.local_floor(145, 5) == 60.0);   // row 150 is within ±5
  CHECK(med.local_floor(199, 5) == 60.0);   // clipped at the last row
  // Targets (row, intensity): near field 170 (floor 5: kept); 170 at row 147 (floor 60 from
  // row 150 within ±5: dropped); 170 in the far field (dropped); 250 in the far field (kept).
  const int col = 128;
  const std::pair<int, uint8_t> targets[] = {{100, 170}, {147, 170}, {170, 170}, {185, 250}};
  for (const auto& [row, value] : targets) {
    h.image[static_cast<size_t>(row) * h.cols + col] = value;
    v.image[static_cast<size_t>(row) * v.cols + col] = value;
  }
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;  // one-cell targets
  cfg.noise_floor_factor = 0.0;
  const FusionResult all = fuse_pair(h, v, cfg);
  REQUIRE(all.points.size() == 4);
  cfg.noise_floor_factor = 3.0;
  const FusionResult gated = fuse_pair(h, v, cfg);
  REQUIRE(gated.points.size() == 2);
  CHECK(gated.points[0].range_m == Approx(h.range_of_row(100)));
  CHECK(gated.points[1].range_m == Approx(h.range_of_row(185)));
  cfg.noise_floor_rows = 0;  // only the row's own median: row 147's floor is 5
  CHECK(fuse_pair(h, v, cfg).points.size() == 3);
}

TEST_CASE("RowMedians is each row's lower median, 8- and 16-bit, on random images", "[unit][rapidcheck]") {
  rc::prop("RowMedians(row) == nth_element's lower median", [] {
    const int bpp = *rc::gen::element(1, 2);
    const int rows = *rc::gen::inRange(1, 6), cols = *rc::gen::inRange(1, 700);
    // Few distinct values (speckle-like ties) or the full range.
    const int top = *rc::gen::element(3, 255, 65535);
    SonarPing p;
    p.rows = static_cast<uint16_t>(rows);
    p.cols = static_cast<uint16_t>(cols);
    p.bytes_per_pixel = static_cast<uint8_t>(bpp);
    const int vmax = bpp == 1 ? std::min(top, 255) : top;
    const auto px = *rc::gen::container<std::vector<int>>(static_cast<size_t>(rows * cols), rc::gen::inRange(0, vmax + 1));
    p.image.resize(px.size() * static_cast<size_t>(bpp));
    for (size_t i = 0; i < px.size(); ++i) {
      if (bpp == 1) {
        p.image[i] = static_cast<uint8_t>(px[i]);
      } else {
        p.image[2 * i] = static_cast<uint8_t>(px[i] & 0xff);
        p.image[2 * i + 1] = static_cast<uint8_t>(px[i] >> 8);
      }
    }
    RowMedians med(p);
    for (int r = 0; r < rows; ++r) {
      std::vector<int> line(px.begin() + r * cols, px.begin() + (r + 1) * cols);
      const auto mid = line.begin() + (cols - 1) / 2;
      std::nth_element(line.begin(), mid, line.end());
      RC_ASSERT(med(r) == static_cast<double>(*mid));
    }
  });
}

TEST_CASE("sloped_face_elevation: the run's near end at -a, its far end at +a, linear between", "[unit]") {
  const double a = 10.0 * kDeg;
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
  auto hv = flat_pair();  // named, not a structured binding: the lambdas below use h and v
  SonarPing& h = hv.first;
  SonarPing& v = hv.second;
  const int col = 128, row = 110, near_row = 80, far_row = 140;
  auto put = [](SonarPing& p, int r, int c, uint8_t x) { p.image[static_cast<size_t>(r) * p.cols + static_cast<size_t>(c)] = x; };
  const int col_v = nearest_col(v, 5.0 * kDeg);
  put(v, row, col_v, 250);
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;
  cfg.slope_run_floor = 0.2;  // the run (60) is above 0.2 x 250, the return
  cfg.slope_v_span_deg = 0.0;  // checked at the end
  auto fuse_with_run = [&](int r0, int r1) {
    SonarPing hh = h;
    for (int r = r0; r <= r1; ++r) put(hh, r, col, 60);
    put(hh, row, col, 250);
    return fuse_pair(hh, v, cfg);
  };
  const double a = cfg.overlap_deg * kDeg;
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
  CHECK(std::abs(p.elevation_rad - v.bearings_rad[static_cast<size_t>(col_v)]) > 4.0 * kDeg);
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

  // A run as short as a wall's (5 rows, 0.2 m < 8 x 0.09 m): Eq. 6's elevation.
  cfg.slope_run_ratio = 8.0;
  const FusionResult wall = fuse_with_run(row - 2, row + 2);
  REQUIRE(wall.points.size() == 1);
  CHECK(wall.sloped_face == 0);
  CHECK(wall.points[0].elevation_rad == Approx(v.bearings_rad[static_cast<size_t>(col_v)]));
  CHECK(wall.points[0].run_far_m - wall.points[0].run_near_m == Approx(4 * h.range_resolution_m));

  // Gaps of up to slope_run_max_gap rows are bridged; a wider one ends the run.
  SonarPing gapped = h;
  for (int r = near_row; r <= far_row; ++r) put(gapped, r, col, (r == 95 || r == 96) ? 5 : 60);
  put(gapped, row, col, 250);
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
  put(v, 100, nearest_col(v, -8.0 * kDeg), 250);
  put(v, 120, nearest_col(v, 8.0 * kDeg), 250);
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
  auto put = [](SonarPing& p, int r, int c, uint8_t x) { p.image[static_cast<size_t>(r) * p.cols + static_cast<size_t>(c)] = x; };
  const int col = 128, row = 130, near_row = 80, far_row = 140;
  for (int r = near_row; r <= far_row; ++r) put(h, r, col, 60);
  put(h, row, col, 250);
  const int col_v = nearest_col(v, 3.0 * kDeg);
  put(v, row, col_v, 250);
  put(v, 85, nearest_col(v, -8.0 * kDeg), 250);
  FusionConfig cfg;
  cfg.min_confidence = 0.0;
  cfg.cfar_h.min_neighbours = cfg.cfar_v.min_neighbours = 0;
  cfg.slope_run_floor = 0.2;
  const double a = cfg.overlap_deg * kDeg;
  const double linear = -a + 2.0 * a * (h.range_of_row(row) - h.range_of_row(near_row)) /
                                 (h.range_of_row(far_row) - h.range_of_row(near_row));
  REQUIRE(linear > 6.0 * kDeg);
  const FusionResult clamped = fuse_pair(h, v, cfg);
  REQUIRE(clamped.points.size() == 1);
  CHECK(clamped.sloped_face == 1);
  CHECK(clamped.points[0].elevation_rad == Approx(v.bearings_rad[static_cast<size_t>(col_v)]));
  cfg.slope_top_from_v = false;
  const FusionResult as_run = fuse_pair(h, v, cfg);
  REQUIRE(as_run.points.size() == 1);
  CHECK(as_run.points[0].elevation_rad == Approx(linear).margin(1e-6));
  cfg.slope_top_from_v = true;
  put(v, 120, nearest_col(v, 8.0 * kDeg), 250);
  const FusionResult higher = fuse_pair(h, v, cfg);
  REQUIRE(higher.points.size() == 1);
  CHECK(higher.points[0].elevation_rad == Approx(linear).margin(1e-6));
}
