// Simulator properties: a small sphere anywhere in the horizontal sonar's fan appears at its
// range and bearing; out of the aperture it leaves the image untouched.
#include <catch2/catch.hpp>
#include <rapidcheck/catch.h>

#include <cmath>
#include <numbers>

#include "hal/sim/primitives.hpp"
#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {

TEST_CASE("sim: a sphere in the fan appears at its range and bearing", "[property]") {
  rc::prop("sphere centroid matches its placement", [] {
    constexpr double kDeg = std::numbers::pi / 180.0;
    const double range = *rc::gen::inRange(40, 250) / 10.0;          // 4 .. 25 m
    const double bearing = *rc::gen::inRange(-55, 56) * kDeg;        // inside the 130 deg swath
    const double elevation = *rc::gen::inRange(-4, 5) * kDeg;         // inside the 20 deg aperture
    const double radius = 0.3;
    TriangleMesh m;
    MeshBuilder(m).sphere(spherical_to_cartesian(range, bearing, elevation), radius, 12, {3, SemanticClass::kOther});
    SonarModelConfig cfg;
    cfg.noise_floor = 0.0;
    const SonarRenderer renderer(m, cfg, Resolution::kReduced, 1);
    const auto r = renderer.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(1), 0);
    double w = 0, rr = 0, bb = 0;
    for (int i = 0; i < r.ping.rows; ++i) {
      for (int j = 0; j < r.ping.cols; ++j) {
        const double v = r.ping.at(i, j);
        w += v;
        rr += v * r.ping.range_of_row(i);
        bb += v * r.ping.bearings_rad[static_cast<size_t>(j)];
      }
    }
    RC_ASSERT(w > 0);
    RC_ASSERT(std::abs(rr / w - (range - radius)) < 0.3);
    RC_ASSERT(std::abs(bb / w - bearing) < std::max(0.8 * kDeg, 0.6 * radius / range));
  });
}

}  // namespace orthosonar::sim
