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
using orthosonar::perception::testing::flat_pair;
using orthosonar::perception::testing::nearest_col;
using orthosonar::perception::testing::set_pixel;

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
  for (int k = 0; k < 7; ++k) set_pixel(h, row, mid - 3 + k, blur[k]);
  set_pixel(v, row, mid, 250);
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
    set_pixel(h, row, col, value);
    set_pixel(v, row, col, value);
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
