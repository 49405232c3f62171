// SE(2)/SE(3) algebra and interpolation properties (seeds printed by rapidcheck;
// set RC_PARAMS="seed=..." to replay a failure).
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "core/geometry.hpp"
#include "property_tests/generators.hpp"

using namespace orthosonar;

namespace {
using property::uniform;
SE2 any_se2() { return {uniform(-50, 50), uniform(-50, 50), uniform(-3.1, 3.1)}; }
SE3 any_se3() {
  return se3_from_xyz_rpy(uniform(-50, 50), uniform(-50, 50), uniform(-20, 20), uniform(-1.4, 1.4),
                          uniform(-1.4, 1.4), uniform(-3.1, 3.1));
}
}  // namespace

TEST_CASE("SE2 compose with inverse is identity", "[property]") {
  rc::prop("T * T^-1 == I and T^-1 * T == I", [] {
    const SE2 T = any_se2();
    for (const SE2 I : {T * T.inverse(), T.inverse() * T}) {
      RC_ASSERT(std::abs(I.x) < 1e-9);
      RC_ASSERT(std::abs(I.y) < 1e-9);
      RC_ASSERT(std::abs(I.theta) < 1e-12);
    }
  });
}

TEST_CASE("SE2 composition is associative and matches matrices", "[property]") {
  rc::prop("(A B) C == A (B C) == matrix product", [] {
    const SE2 A = any_se2(), B = any_se2(), C = any_se2();
    const SE2 l = (A * B) * C, r = A * (B * C);
    const Eigen::Matrix3d M = A.matrix() * B.matrix() * C.matrix();
    RC_ASSERT((l.matrix() - r.matrix()).norm() < 1e-9);
    RC_ASSERT((l.matrix() - M).norm() < 1e-9);
  });
}

TEST_CASE("SE3 compose with inverse is identity", "[property]") {
  rc::prop("T * T^-1 == I", [] {
    const SE3 T = any_se3();
    RC_ASSERT(((T * T.inverse()).matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-9);
    RC_ASSERT(((T.inverse() * T).matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-9);
  });
}

TEST_CASE("SE3 from SE2 round-trips the planar part", "[property]") {
  rc::prop("se2_from_se3(se3_from_se2(T, z, r, p)) == T", [] {
    const SE2 T = any_se2();
    const SE3 T3 = se3_from_se2(T, uniform(-10, 0), uniform(-0.5, 0.5), uniform(-0.5, 0.5));
    const SE2 back = se2_from_se3(T3);
    RC_ASSERT(std::abs(back.x - T.x) < 1e-9);
    RC_ASSERT(std::abs(back.y - T.y) < 1e-9);
    RC_ASSERT(std::abs(wrap_angle(back.theta - T.theta)) < 1e-9);
  });
}

TEST_CASE("interpolation hits both endpoints and is continuous", "[property]") {
  rc::prop("SE3 interpolate", [] {
    const SE3 a = any_se3(), b = any_se3();
    RC_ASSERT((interpolate(a, b, 0.0).matrix() - a.matrix()).norm() < 1e-9);
    RC_ASSERT((interpolate(a, b, 1.0).matrix() - b.matrix()).norm() < 1e-9);
    const double s = uniform(0.0, 0.999);
    const SE3 p = interpolate(a, b, s), q = interpolate(a, b, s + 1e-6);
    // A step of 1e-6 in s moves at most 1e-6 * (distance + pi) (rotation angle <= pi).
    const double bound = 1e-6 * ((b.translation() - a.translation()).norm() + std::numbers::pi) + 1e-9;
    RC_ASSERT((q.translation() - p.translation()).norm() <= bound);
    RC_ASSERT(Quat(p.rotation()).angularDistance(Quat(q.rotation())) <= bound);
  });
  rc::prop("SE2 interpolate", [] {
    const SE2 a = any_se2(), b = any_se2();
    const SE2 i0 = interpolate(a, b, 0.0), i1 = interpolate(a, b, 1.0);
    RC_ASSERT((i0.matrix() - a.matrix()).norm() < 1e-9);
    RC_ASSERT((i1.matrix() - b.matrix()).norm() < 1e-9);
    const double s = uniform(0.0, 0.999);
    const SE2 p = interpolate(a, b, s), q = interpolate(a, b, s + 1e-6);
    RC_ASSERT(std::abs(wrap_angle(q.theta - p.theta)) <= 1e-6 * std::numbers::pi + 1e-12);
  });
}

TEST_CASE("spherical to Cartesian round-trips (Eq. 1)", "[property]") {
  rc::prop("cartesian_to_spherical inverts Eq. 1", [] {
    const double r = uniform(0.05, 30), th = uniform(-1.2, 1.2), ph = uniform(-1.2, 1.2);
    const Vec3 back = cartesian_to_spherical(spherical_to_cartesian(r, th, ph));
    RC_ASSERT(std::abs(back.x() - r) < 1e-9);
    RC_ASSERT(std::abs(back.y() - th) < 1e-9);
    RC_ASSERT(std::abs(back.z() - ph) < 1e-9);
  });
}
