// The fusion round trip (issue 8): a 3D point inside the overlap of both fields of view,
// projected into the horizontal image (range, bearing θ) and the vertical image (range,
// elevation φ, the v sonar being h rolled +90° about x), fuses back to itself within the
// images' discretisation: one range bin plus the local beam widths at that range.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/perception/fusion.hpp"
#include "core/random.hpp"

using namespace orthosonar;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double uniform(double lo, double hi) {
  const int k = *rc::gen::inRange(0, 1000001);
  return lo + (hi - lo) * (static_cast<double>(k) / 1000000.0);
}

// 240 bins x 256 beams over 130° with a denser centre (like the Oculus tables); a dark,
// speckled background well under the CFAR gate.
SonarPing background(SonarMount mount, uint64_t seed) {
  SonarPing p;
  p.mount = mount;
  p.rows = 240;
  p.cols = 256;
  p.range_resolution_m = 0.05;
  for (int c = 0; c < p.cols; ++c) {
    const double u = -1.0 + 2.0 * (c + 0.5) / p.cols;
    p.bearings_rad.push_back(65.0 * kDeg * (u + 0.3 * u * u * u) / 1.3);
  }
  Rng rng(seed);
  p.image.resize(static_cast<size_t>(p.rows) * p.cols);
  for (auto& x : p.image) x = static_cast<uint8_t>(std::min(40.0, rng.exponential(6.0)));
  return p;
}

int nearest_col(const SonarPing& p, double angle) {
  int best = 0;
  for (int c = 1; c < p.cols; ++c)
    if (std::abs(p.bearings_rad[static_cast<size_t>(c)] - angle) <
        std::abs(p.bearings_rad[static_cast<size_t>(best)] - angle))
      best = c;
  return best;
}

// A 3x3 blob symmetric under a 90° rotation, at the pixel nearest (range, angle).
void draw_target(SonarPing& p, double range_m, double angle_rad) {
  const int row = static_cast<int>(std::lround(range_m / p.range_resolution_m)) - 1;
  const int col = nearest_col(p, angle_rad);
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc)
      p.image[static_cast<size_t>((row + dr) * p.cols + col + dc)] = (dr == 0 && dc == 0) ? 240 : 180;
}

}  // namespace

TEST_CASE("Fusion round trip: a 3D point in the overlap fuses back to itself", "[property]") {
  rc::prop("point -> h and v images -> fused point", [] {
    const double range = uniform(1.5, 10.0);
    const double theta = uniform(-9.0, 9.0) * kDeg;
    const double phi = uniform(-9.0, 9.0) * kDeg;
    // Both sonars at the vehicle origin so the construction is exact up to pixels.
    perception::FusionConfig cfg;
    cfg.T_V_h = se3_from_xyz_rpy(0, 0, 0, 0, 0, 0);
    cfg.T_V_v = se3_from_xyz_rpy(0, 0, 0, std::numbers::pi / 2.0, 0, 0);
    const Vec3 p_V = spherical_to_cartesian(range, theta, phi);
    const Vec3 p_v = cfg.T_V_v.inverse() * p_V;  // in the vertical sonar's frame
    const double elevation_seen_by_v = std::atan2(p_v.y(), p_v.x());

    const uint64_t seed = static_cast<uint64_t>(*rc::gen::inRange(0, 1 << 30));
    SonarPing h = background(SonarMount::kHorizontal, derive_seed(seed, 1));
    SonarPing v = background(SonarMount::kVertical, derive_seed(seed, 2));
    draw_target(h, range, theta);
    draw_target(v, p_v.norm(), elevation_seen_by_v);

    const perception::FusionResult r = perception::fuse_pair(h, v, cfg);
    // The 3x3 blob gives up to three detections per range bin in each image, so up to a
    // few points; every one must lie on the target.
    RC_ASSERT(!r.points.empty());
    RC_ASSERT(r.points.size() <= 9u);
    // Two range bins, plus 2.5 beam widths (the table's widest, at the centre ~0.45°) of
    // arc in each angle, plus the small skew of φ seen by v at θ != 0 (< 0.2°).
    const double arc = range * (2.5 * 0.45 + 0.2) * kDeg;
    const double tol = 2.0 * h.range_resolution_m + std::sqrt(2.0) * arc;
    for (const auto& fp : r.points) {
      const Vec3 got = fp.p_V.cast<double>();
      RC_LOG() << "target " << p_V.transpose() << " fused " << got.transpose() << " tol " << tol << "\n";
      RC_ASSERT((got - p_V).norm() <= tol);
    }
  });
}
