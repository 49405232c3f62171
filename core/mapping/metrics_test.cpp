#include "core/mapping/metrics.hpp"

#include <catch2/catch.hpp>
#include <numbers>

#include "core/mapping/mesh_distance.hpp"
#include "core/mapping/perception_metrics.hpp"
#include "core/random.hpp"

using namespace orthosonar;
using namespace orthosonar::mapping;

namespace {
constexpr double kPiMetricsTest = std::numbers::pi;

TriangleMesh random_mesh(Rng& rng, int n) {
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3f c(static_cast<float>(rng.uniform(-10, 10)), static_cast<float>(rng.uniform(-10, 10)),
                            static_cast<float>(rng.uniform(-5, 5)));
    const int base = static_cast<int>(m.vertices.size());
    for (int k = 0; k < 3; ++k)
      m.vertices.push_back(c + Eigen::Vector3f(static_cast<float>(rng.uniform(-1, 1)),
                                               static_cast<float>(rng.uniform(-1, 1)),
                                               static_cast<float>(rng.uniform(-1, 1))));
    m.triangles.emplace_back(base, base + 1, base + 2);
    m.object_id.push_back(1);
    m.semantic.push_back(SemanticClass::kOther);
  }
  return m;
}

}  // namespace

TEST_CASE("closest point on a triangle covers every Voronoi region", "[unit]") {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK((closest_point_on_triangle({0.2, 0.2, 3}, a, b, c) - Eigen::Vector3d(0.2, 0.2, 0)).norm() < 1e-12);
  CHECK((closest_point_on_triangle({-1, -1, 0}, a, b, c) - a).norm() < 1e-12);
  CHECK((closest_point_on_triangle({2, -1, 0}, a, b, c) - b).norm() < 1e-12);
  CHECK((closest_point_on_triangle({-1, 2, 0}, a, b, c) - c).norm() < 1e-12);
  CHECK((closest_point_on_triangle({0.5, -1, 1}, a, b, c) - Eigen::Vector3d(0.5, 0, 0)).norm() < 1e-12);
  CHECK((closest_point_on_triangle({-1, 0.5, 0}, a, b, c) - Eigen::Vector3d(0, 0.5, 0)).norm() < 1e-12);
  CHECK((closest_point_on_triangle({1, 1, 0}, a, b, c) - Eigen::Vector3d(0.5, 0.5, 0)).norm() < 1e-12);
  // Degenerate triangle (a segment).
  CHECK((closest_point_on_triangle({0.5, 1, 0}, a, b, b) - Eigen::Vector3d(0.5, 0, 0)).norm() < 1e-12);
}

TEST_CASE("BVH distance equals brute force on random meshes", "[unit]") {
  Rng rng(7);
  const TriangleMesh mesh = random_mesh(rng, 500);
  const MeshDistance md(mesh);
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p(rng.uniform(-14, 14), rng.uniform(-14, 14), rng.uniform(-8, 8));
    REQUIRE(md.distance(p) == md.distance_brute_force(p));
  }
  CHECK(std::isinf(MeshDistance(TriangleMesh{}).distance({0, 0, 0})));
}

TEST_CASE("the nearest triangle's normal: a wall's is horizontal, a floor's vertical, a slope's between", "[unit]") {
  // A 45-degree slope face along x (rising to +y), a vertical wall at x = 10 and a floor at z = -5.
  TriangleMesh m;
  m.vertices = {{-5, 0, -2}, {5, 0, -2}, {5, 4, 2}, {-5, 4, 2},        // slope
                {10, -5, -5}, {10, 5, -5}, {10, 5, 5}, {10, -5, 5},    // wall
                {-20, -20, -5}, {20, -20, -5}, {20, 20, -5}, {-20, 20, -5}};  // floor
  for (int q = 0; q < 3; ++q) {
    m.triangles.emplace_back(4 * q, 4 * q + 1, 4 * q + 2);
    m.triangles.emplace_back(4 * q, 4 * q + 2, 4 * q + 3);
  }
  m.object_id.assign(m.triangles.size(), 1);
  m.semantic.assign(m.triangles.size(), SemanticClass::kOther);
  const MeshDistance md(m);
  auto angle = [&](const Eigen::Vector3d& p) {
    const MeshDistance::Nearest n = md.nearest(p);
    CHECK(n.distance == md.distance(p));
    CHECK(n.normal.norm() == Approx(1.0));
    return surface_angle_from_vertical_deg(n.normal);
  };
  CHECK(angle({0, 1.5, 0.3}) == Approx(45.0).margin(1e-9));  // just above the slope
  CHECK(angle({9.8, 0, 0}) == Approx(0.0).margin(1e-9));     // beside the wall
  CHECK(angle({-15, -15, -4.9}) == Approx(90.0).margin(1e-9));  // over the floor
  CHECK(MeshDistance(TriangleMesh{}).nearest({0, 0, 0}).normal.isZero());
}

TEST_CASE("voxel centroids and coverage", "[unit]") {
  const std::vector<Eigen::Vector3f> pts = {{0.01f, 0.01f, 0.01f}, {0.03f, 0.05f, 0.07f}, {-0.01f, 0.0f, 0.0f},
                                            {0.25f, 0.0f, 0.0f}};
  CHECK(coverage_voxels(pts) == 3);
  const auto c = voxel_centroids(pts);
  REQUIRE(c.size() == 3);
  CHECK(c[0].x() == Approx(-0.01));           // voxel -1 first
  CHECK(c[1].x() == Approx(0.02));            // mean of the two in voxel 0
  CHECK(c[1].z() == Approx(0.04));
  CHECK(c[2].x() == Approx(0.25));
}

TEST_CASE("accuracy of points on a plane at known offsets", "[unit]") {
  TriangleMesh plane;
  plane.vertices = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
  plane.triangles = {{0, 1, 2}, {0, 2, 3}};
  plane.object_id = {1, 1};
  plane.semantic = {SemanticClass::kSeafloor, SemanticClass::kSeafloor};
  const MeshDistance md(plane);
  const auto s = accuracy({{0, 0, 0.1f}, {1, 1, -0.3f}}, md);
  CHECK(s.count == 2);
  CHECK(s.mae_m == Approx(0.2));
  CHECK(s.rmse_m == Approx(std::sqrt((0.01 + 0.09) / 2)));
}

TEST_CASE("ATE against a known trajectory", "[unit]") {
  std::vector<TruthPose> truth;
  for (int i = 0; i <= 10; ++i) {
    TruthPose p;
    p.stamp = Time::from_s(i);
    p.p_W = Vec3(static_cast<double>(i), 0, 0);
    truth.push_back(p);
  }
  CHECK(truth_position_at(truth, Time::from_ms(2500))->x() == Approx(2.5));
  CHECK_FALSE(truth_position_at(truth, Time::from_s(11)).has_value());
  // Offsets 0.3 and 0.4 in y: RMSE = sqrt((0.09 + 0.16) / 2).
  const std::vector<StampedPosition> est = {{Time::from_ms(1500), Vec3(1.5, 0.3, 0)},
                                            {Time::from_ms(7250), Vec3(7.25, 0, -0.4)},
                                            {Time::from_s(20), Vec3(0, 0, 0)}};
  CHECK(*absolute_trajectory_error(est, truth) == Approx(std::sqrt(0.125)));
  CHECK(*absolute_trajectory_error({{Time::from_s(3), Vec3(3, 0, 0)}}, truth) == 0.0);
  CHECK_FALSE(absolute_trajectory_error({}, truth).has_value());
}

TEST_CASE("keyframe heading error against truth: wrapped, signed, pitch and roll ignored", "[unit]") {
  // Truth turns from 170 deg to 190 deg (-170) over 2 s: the error wraps across +-180.
  std::vector<TruthPose> truth(2);
  truth[0].stamp = Time::from_s(0);
  truth[0].q_W_V = Quat(Eigen::AngleAxisd(170.0 * kPiMetricsTest / 180.0, Vec3::UnitZ()));
  truth[1].stamp = Time::from_s(2);
  truth[1].q_W_V = Quat(Eigen::AngleAxisd(190.0 * kPiMetricsTest / 180.0, Vec3::UnitZ()));
  auto est_at = [](double s, double yaw_deg, double pitch_deg) {
    return StampedPose{Time::from_seconds(s), se3_from_xyz_rpy(0, 0, 0, 0.0, pitch_deg * kPiMetricsTest / 180.0, yaw_deg * kPiMetricsTest / 180.0)};
  };
  // At 1 s the truth is at 180 deg: an estimate of -179 deg is +1 deg off, one of 177 deg
  // -3 deg; one pitched by 5 deg at the truth's yaw is 0 off; one after the truth span is
  // skipped.
  const std::vector<StampedPose> est = {est_at(1, -179, 0), est_at(1, 177, 0), est_at(2, 190, 5), est_at(3, 0, 0)};
  const auto h = heading_error(est, truth);
  REQUIRE(h.has_value());
  CHECK(h->count == 3);
  CHECK(h->rms_deg == Approx(std::sqrt((1.0 + 9.0 + 0.0) / 3.0)).epsilon(1e-9));
  CHECK(h->mean_deg == Approx(-2.0 / 3.0).epsilon(1e-9));
  CHECK(h->max_abs_deg == Approx(3.0).epsilon(1e-9));
  CHECK_FALSE(heading_error({est_at(5, 0, 0)}, truth).has_value());
  CHECK_FALSE(heading_error({}, truth).has_value());
}

TEST_CASE("truth pose interpolated in position and orientation", "[unit]") {
  std::vector<TruthPose> truth(2);
  truth[0].stamp = Time::from_s(1);
  truth[0].p_W = Vec3(0, 0, -2);
  truth[1].stamp = Time::from_s(3);
  truth[1].p_W = Vec3(4, 2, -2);
  truth[1].q_W_V = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()));
  const auto mid = truth_pose_at(truth, Time::from_s(2));
  REQUIRE(mid.has_value());
  CHECK((mid->translation() - Vec3(2, 1, -2)).norm() < 1e-12);
  CHECK(Eigen::AngleAxisd(mid->rotation()).angle() == Approx(0.2));
  CHECK(Eigen::AngleAxisd(mid->rotation()).axis().z() == Approx(1.0));
  const auto end = truth_pose_at(truth, Time::from_s(3));
  REQUIRE(end.has_value());
  CHECK((end->translation() - Vec3(4, 2, -2)).norm() < 1e-12);
  CHECK_FALSE(truth_pose_at(truth, Time::from_ms(999)).has_value());
  CHECK_FALSE(truth_pose_at({}, Time::from_s(2)).has_value());
}
