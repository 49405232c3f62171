// Known-answer tests of sonar image formation: targets at known range, bearing, elevation.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <thread>
#include <vector>

#include "hal/sim/primitives.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TriangleMesh sphere_at(const Vec3& c, double radius) {
  TriangleMesh m;
  MeshBuilder(m).sphere(c, radius, 16, {7, SemanticClass::kOther});
  return m;
}

SonarModelConfig quiet_config() {
  SonarModelConfig c;
  apply_profile(c, SonarProfile::kClean);  // the geometry of image formation, no artefacts
  c.noise_floor = 0.0;  // every non-zero pixel is an echo
  return c;
}

// Intensity-weighted centroid (range m, bearing rad) of a ping; total weight in .z().
Vec3 centroid(const SonarPing& p) {
  Vec3 acc = Vec3::Zero();
  for (int r = 0; r < p.rows; ++r) {
    for (int c = 0; c < p.cols; ++c) {
      const double w = p.at(r, c);
      acc += w * Vec3(p.range_of_row(r), p.bearings_rad[static_cast<size_t>(c)], 1.0);
    }
  }
  return {acc.x() / acc.z(), acc.y() / acc.z(), acc.z()};
}

}  // namespace

TEST_CASE("a small sphere peaks at its range and bearing", "[hal]") {
  const double range = 10.0, bearing = 20.0 * kDeg, radius = 0.3;
  const TriangleMesh m = sphere_at(spherical_to_cartesian(range, bearing, 0.0), radius);
  const SonarRenderer renderer(m, quiet_config(), Resolution::kReduced, 1);
  const SonarRender r = renderer.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(1), 0);
  const Vec3 c = centroid(r.ping);
  REQUIRE(c.z() > 0);
  CHECK(c.x() == Approx(range - radius).margin(0.25));
  CHECK(c.y() == Approx(bearing).margin(0.6 * kDeg));
  // The brightest pixel sits on the sphere's front.
  int best_r = 0, best_c = 0;
  for (int i = 0; i < r.ping.rows; ++i)
    for (int j = 0; j < r.ping.cols; ++j)
      if (r.ping.at(i, j) > r.ping.at(best_r, best_c)) best_r = i, best_c = j;
  CHECK(r.ping.range_of_row(best_r) == Approx(range - radius).margin(0.3));
  CHECK(r.ping.bearings_rad[static_cast<size_t>(best_c)] == Approx(bearing).margin(2.0 * kDeg));
}

TEST_CASE("a flat wall appears at its distance across beams", "[hal]") {
  const double d = 8.0;
  TriangleMesh m;
  MeshBuilder(m).box({d + 0.5, 0, 0}, {1.0, 60.0, 30.0}, 0.0, {2, SemanticClass::kSeawall});
  const SonarRenderer renderer(m, quiet_config(), Resolution::kReduced, 3);
  const SonarRender r = renderer.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(1), 5);
  int checked = 0, good = 0;
  for (int c = 0; c < r.ping.cols; ++c) {
    const double th = r.ping.bearings_rad[static_cast<size_t>(c)];
    if (std::abs(th) > 50 * kDeg) continue;
    int first = -1;
    for (int row = 0; row < r.ping.rows && first < 0; ++row) if (r.ping.at(row, c) > 0) first = row;
    ++checked;
    if (first >= 0 && std::abs(r.ping.range_of_row(first) - d / std::cos(th)) <= 1.5 * r.ping.range_resolution_m) ++good;
  }
  CHECK(checked > 100);
  CHECK(good >= checked * 95 / 100);
}

TEST_CASE("a target outside the aperture is invisible", "[hal]") {
  const TriangleMesh above = sphere_at(spherical_to_cartesian(10.0, 0.0, 16.0 * kDeg), 0.5);
  const TriangleMesh empty;
  SonarModelConfig cfg;  // with the noise floor: the image must equal an empty scene's
  const SonarRenderer with(above, cfg, Resolution::kReduced, 9);
  const SonarRenderer without(empty, cfg, Resolution::kReduced, 9);
  const auto a = with.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(2), 17);
  const auto b = without.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(2), 17);
  CHECK(a.ping.image == b.ping.image);
  // ... and inside the aperture it is not.
  const SonarRenderer inside(sphere_at(spherical_to_cartesian(10.0, 0.0, 5.0 * kDeg), 0.5), cfg, Resolution::kReduced, 9);
  CHECK(inside.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(2), 17).ping.image != b.ping.image);
}

TEST_CASE("the vertical sonar sees a target at its elevation", "[hal]") {
  const double range = 12.0, elevation = -25.0 * kDeg;
  const TriangleMesh m = sphere_at(spherical_to_cartesian(range, 0.0, elevation), 0.3);
  const SonarRenderer renderer(m, quiet_config(), Resolution::kReduced, 1);
  const SE3 T_V_v = se3_from_xyz_rpy(0, 0, 0, std::numbers::pi / 2, 0, 0);  // rolled +90 deg about x
  const auto v = renderer.render(T_V_v, SonarMount::kVertical, Time::from_s(1), 0);
  const Vec3 c = centroid(v.ping);
  REQUIRE(c.z() > 0);
  CHECK(v.ping.part_number == kPartM1200d);
  CHECK(c.x() == Approx(range - 0.3).margin(0.25));
  CHECK(c.y() == Approx(elevation).margin(0.6 * kDeg));
  // The horizontal sonar's aperture (+-10 deg) does not reach -25 deg.
  const auto h = renderer.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(1), 0);
  CHECK(centroid(h.ping).z() == 0);
}

TEST_CASE("same seed same image and another seed other speckle", "[hal]") {
  TriangleMesh m;
  MeshBuilder(m).box({8.5, 0, 0}, {1.0, 60.0, 30.0}, 0.0, {2, SemanticClass::kSeawall});
  const SonarModelConfig cfg;
  const SonarRenderer a(m, cfg, Resolution::kReduced, 5), b(m, cfg, Resolution::kReduced, 5), c(m, cfg, Resolution::kReduced, 6);
  const SE3 T = se3_from_xyz_rpy(0.1, -0.2, 0.0, 0.0, 0.0, 0.2);
  const auto pa = a.render(T, SonarMount::kHorizontal, Time::from_s(3), 42).ping;
  CHECK(pa == b.render(T, SonarMount::kHorizontal, Time::from_s(3), 42).ping);
  CHECK(pa.image != c.render(T, SonarMount::kHorizontal, Time::from_s(3), 42).ping.image);
  CHECK(pa.image != a.render(T, SonarMount::kHorizontal, Time::from_s(3), 43).ping.image);  // per-frame speckle
}

TEST_CASE("labels mark the echoes of an object with its class", "[hal]") {
  const TriangleMesh m = sphere_at({9.0, 0.0, 0.0}, 0.5);
  const SonarRenderer renderer(m, quiet_config(), Resolution::kReduced, 1);
  const auto r = renderer.render(SE3::Identity(), SonarMount::kHorizontal, Time::from_s(1), 3, true);
  REQUIRE(r.labels.semantic.size() == r.ping.image.size());
  size_t labelled = 0;
  for (size_t i = 0; i < r.ping.image.size(); ++i) {
    if (r.labels.semantic[i] != 0) {
      ++labelled;
      CHECK(r.labels.object_id[i] == 7u);
      CHECK(r.labels.semantic[i] == static_cast<uint8_t>(SemanticClass::kOther));
    }
  }
  CHECK(labelled > 5);
}

TEST_CASE("the bearing table is quantised like the device and denser at the centre", "[hal]") {
  const SonarRenderer full(TriangleMesh{}, SonarModelConfig{}, Resolution::kFull, 1);
  const auto& b = full.bearings_rad(SonarMount::kHorizontal);
  REQUIRE(b.size() == 512u);
  CHECK(full.geometry(SonarMount::kHorizontal).range_bins == 600);
  for (double x : b) CHECK(std::abs(x / kDeg * 100.0 - std::round(x / kDeg * 100.0)) < 1e-6);
  CHECK(b.back() == Approx(65.0 * kDeg).margin(0.5 * kDeg));
  CHECK(b[257] - b[256] < b[511] - b[510]);
}

TEST_CASE("the M1200d's 2.1 MHz mode: 60 x 12 deg, 10 m, its own bearing table", "[hal]") {
  SimConfig c;
  REQUIRE(apply_sim_config_yaml("profile: field\nsonar: {vertical_mode: 2.1MHz}\n", c).ok());
  CHECK(c.profile == SonarProfile::kField);
  CHECK(c.sonar.head_v.frequency_hz == 2.1e6);
  const SonarRenderer r(TriangleMesh{}, c.sonar, Resolution::kFull, 1);
  const auto& b = r.bearings_rad(SonarMount::kVertical);
  CHECK(b.back() == Approx(30.0 * kDeg).margin(0.3 * kDeg));
  CHECK(r.bearings_rad(SonarMount::kHorizontal).back() == Approx(65.0 * kDeg).margin(0.5 * kDeg));
  CHECK(r.geometry(SonarMount::kVertical).range_resolution_m == Approx(10.0 / 600));
  const auto ping = r.render(SE3::Identity(), SonarMount::kVertical, Time::from_s(1), 0).ping;
  CHECK(ping.frequency_hz == 2.1e6);
  CHECK(ping.max_range_m() == Approx(10.0).margin(0.02));
  // Bad modes and profiles are errors naming the key.
  SimConfig d;
  const Status bad = apply_sim_config_yaml("sonar: {vertical_mode: 3MHz}\n", d);
  REQUIRE(!bad.ok());
  CHECK(bad.error().message.find("vertical_mode") != std::string::npos);
  CHECK(!apply_sim_config_yaml("profile: muddy\n", d).ok());
  // 20 pings/s at 30 m is within the two-way travel time (25 Hz); 30 is not.
  CHECK(apply_sim_config_yaml("nav: {ping_rate_hz: 20}\n", d).ok());
  CHECK(!apply_sim_config_yaml("nav: {ping_rate_hz: 30}\n", d).ok());
}

TEST_CASE("a ping's image does not depend on the pings rendered before it on its thread", "[hal]") {
  // The renderer keeps its per-ping buffers per thread and clears only what a ping wrote:
  // a ping rendered after others must equal the same ping rendered first on a new thread.
  const Scene scene = *builtin_scene("marina1", 1);
  SonarModelConfig c;
  apply_profile(c, SonarProfile::kField);
  c.seafloor_depth_m = scene.seafloor_depth_m;
  const SonarRenderer r(scene.mesh, c, Resolution::kReduced, 7);
  const SE3 T1 = se3_from_xyz_rpy(-21, 7, -scene.vehicle_depth_m, 0, 0, std::numbers::pi / 2.0);
  const SE3 T2 = se3_from_xyz_rpy(-5, -3, -scene.vehicle_depth_m, 0, 0.2, 0.3);
  for (const SonarMount mount : {SonarMount::kHorizontal, SonarMount::kVertical}) {
    std::vector<uint8_t> first, after, labels_first, labels_after;
    std::thread([&] {
      const SonarRender p = r.render(T2, mount, Time::from_s(2), 9, true);
      first = p.ping.image;
      labels_first = p.labels.semantic;
    }).join();
    std::thread([&] {
      (void)r.render(T1, mount, Time::from_s(1), 3, true);
      (void)r.echo(T1, mount);  // hands its buffer out: the next ping starts from a new one
      (void)r.render(T1, mount, Time::from_s(1), 4, false);
      const SonarRender p = r.render(T2, mount, Time::from_s(2), 9, true);
      after = p.ping.image;
      labels_after = p.labels.semantic;
    }).join();
    CHECK(first == after);
    CHECK(labels_first == labels_after);
  }
}

}  // namespace orthosonar::sim