#include "reports/camera.hpp"

#include <catch2/catch.hpp>

using namespace orthosonar;
using namespace orthosonar::reports;

namespace {
TriangleMesh scene() {
  TriangleMesh m;
  // A 200 m seafloor square at z = -10 and one piling triangle near the origin.
  m.vertices = {{-100, -100, -10}, {100, -100, -10}, {100, 100, -10}, {-100, 100, -10}, {0, 0, -10}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}};
  m.semantic = {SemanticClass::kSeafloor, SemanticClass::kSeafloor, SemanticClass::kPiling};
  m.object_id = {0, 0, 1};
  return m;
}
Trajectory loop() {
  Trajectory t(4);
  t[0].position = {-5, -5, -2};
  t[1].position = {5, -5, -2};
  t[2].position = {5, 5, -2};
  t[3].position = {-5, 5, -2};
  return t;
}
}  // namespace

TEST_CASE("scene bounds come from structures and the truth track, not the seafloor or the cloud", "[report]") {
  const TriangleMesh m = scene();
  const Trajectory t = loop();
  const std::vector<Eigen::Vector3f> far_cloud = {{500, 500, 50}};
  const Bounds b = scene_bounds(&m, &t, far_cloud);
  REQUIRE(b.valid());
  CHECK(b.min.x() == -5.0);
  CHECK(b.max.x() == 5.0);
  CHECK(b.min.z() == -10.0);  // the seafloor's depth still counts
  CHECK(b.max.z() == 0.0);
  // The cloud never moves the camera: the same bounds without it.
  const Bounds b2 = scene_bounds(&m, &t, {});
  CHECK(b2.min == b.min);
  CHECK(b2.max == b.max);
  // Only a cloud: it is the fallback.
  const Bounds b3 = scene_bounds(nullptr, nullptr, far_cloud);
  CHECK(b3.valid());
  CHECK(b3.min.x() == 500.0);
  CHECK_FALSE(scene_bounds(nullptr, nullptr, {}).valid());
}

TEST_CASE("scene bounds stop above the water surface and beyond the sonar reach", "[report]") {
  TriangleMesh m = scene();
  // A mast up to 25 m above the surface, and a far structure 200 m away.
  m.vertices.push_back({0.5f, 0.5f, 25.0f});
  m.vertices.push_back({200.0f, 0.0f, -5.0f});
  m.vertices.push_back({201.0f, 0.0f, -5.0f});
  m.triangles.push_back({5, 6, 7});
  m.triangles.push_back({8, 9, 4});
  for (int i = 0; i < 2; ++i) {
    m.semantic.push_back(SemanticClass::kHull);
    m.object_id.push_back(2);
  }
  const Trajectory t = loop();
  const Bounds b = scene_bounds(&m, &t, {});
  CHECK(b.max.z() == 1.0);
  CHECK(b.max.x() == 5.0 + 30.0);  // clipped to the trajectory box grown by the reach
  CHECK(b.min.z() == -10.0);
}

TEST_CASE("the top camera looks straight down and frames the whole box", "[report]") {
  Bounds b;
  b.extend({-20, -5, -10});
  b.extend({20, 5, 0});
  const double aspect = 1280.0 / 960.0;
  const Camera c = fixed_camera(b, View::kTop, aspect);
  CHECK(c.parallel);
  CHECK(c.position.x() == c.focal_point.x());
  CHECK(c.position.y() == c.focal_point.y());
  CHECK(c.position.z() > b.max.z());
  CHECK(c.view_up == Eigen::Vector3d::UnitY());
  // Visible half-width (parallel scale * aspect) covers the box's half-width around the focal point.
  CHECK(c.parallel_scale_m * aspect >= 20.0 + std::abs(c.focal_point.x()));
  CHECK(c.parallel_scale_m >= 5.0);
  const Camera o = fixed_camera(b, View::kOblique, aspect);
  CHECK_FALSE(o.parallel);
  CHECK(o.position.z() > b.max.z());
  CHECK((o.position - o.focal_point).norm() > 0.5 * b.size().norm());
  // Deterministic: the same input gives the same camera.
  CHECK(fixed_camera(b, View::kOblique, aspect).position == o.position);
}
