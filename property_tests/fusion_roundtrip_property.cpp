// The fusion round trip (issue 8): a 3D point inside the overlap of both fields of view,
// projected into the horizontal image (range, bearing θ) and the vertical image (range,
// elevation φ, the v sonar being h rolled +90° about x), fuses back to itself within the
// images' discretisation: one range bin plus the local beam widths at that range.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/perception/fusion.hpp"
#include "core/perception/synthetic_pings.hpp"
#include "core/random.hpp"
#include "property_tests/generators.hpp"

using namespace orthosonar;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using property::uniform;

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
    // 240 bins x 256 beams on a dark speckled background, well under the CFAR gate.
    SonarPing h = perception::testing::speckle_ping(SonarMount::kHorizontal, 240, 256, derive_seed(seed, 1), 6.0, 40.0);
    SonarPing v = perception::testing::speckle_ping(SonarMount::kVertical, 240, 256, derive_seed(seed, 2), 6.0, 40.0);
    perception::testing::draw_blob(h, range, theta, 240, 180);
    perception::testing::draw_blob(v, p_v.norm(), elevation_seen_by_v, 240, 180);

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
