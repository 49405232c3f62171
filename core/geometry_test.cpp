#include "core/geometry.hpp"

#include <catch2/catch.hpp>
#include <numbers>

using namespace orthosonar;

TEST_CASE("wrap_angle maps into the half-open interval from -pi to pi", "[unit]") {
  CHECK(wrap_angle(3 * std::numbers::pi) == Approx(std::numbers::pi));
  CHECK(wrap_angle(-std::numbers::pi) == Approx(std::numbers::pi));
  CHECK(wrap_angle(0.5) == Approx(0.5));
  CHECK(wrap_angle(-7.0) == Approx(-7.0 + 2 * std::numbers::pi));
}

TEST_CASE("SE2 acts as a rotation then a translation", "[unit]") {
  const SE2 T{1.0, 2.0, std::numbers::pi / 2};
  const Vec2 p = T * Vec2(1.0, 0.0);
  CHECK(p.x() == Approx(1.0));
  CHECK(p.y() == Approx(3.0));
}

TEST_CASE("SE2 interpolation takes the short way round", "[unit]") {
  const SE2 a{0, 0, 3.0}, b{0, 0, -3.0};
  const SE2 mid = interpolate(a, b, 0.5);
  CHECK(std::abs(mid.theta) == Approx(std::numbers::pi));
}

TEST_CASE("spherical_to_cartesian matches Eq. 1 on axes", "[unit]") {
  CHECK(spherical_to_cartesian(2.0, 0, 0).isApprox(Vec3(2, 0, 0)));
  CHECK(spherical_to_cartesian(2.0, std::numbers::pi / 2, 0).isApprox(Vec3(0, 2, 0), 1e-12));
  CHECK(spherical_to_cartesian(2.0, 0.3, std::numbers::pi / 2).isApprox(Vec3(0, 0, 2), 1e-12));
}

TEST_CASE("roll, pitch and yaw round-trip through a rotation", "[unit]") {
  const SE3 T = se3_from_xyz_rpy(1, 2, 3, 0.1, -0.2, 2.5);
  const Vec3 rpy = rpy_from_rotation(T.rotation());
  CHECK(rpy.x() == Approx(0.1));
  CHECK(rpy.y() == Approx(-0.2));
  CHECK(rpy.z() == Approx(2.5));
}
