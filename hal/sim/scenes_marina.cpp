// marina1 and marina2 (docs/SCENES.md). Layout fixed; the seed jitters piling positions
// and radii, picks which slips hold boats, shapes the seafloor and scatters debris.
#include <cmath>
#include <numbers>

#include "hal/sim/scenes_builtin.hpp"

namespace orthosonar::sim::detail {
namespace {

// A row of finger docks hanging off a main dock, with pilings at the finger ends.
void finger_row(SceneAssembly& a, Rng& rng, double main_y, double finger_end_y,
                const std::vector<double>& finger_x) {
  const double dir = finger_end_y < main_y ? -1.0 : 1.0;
  const double len = std::abs(finger_end_y - main_y) - 1.25;
  for (double x : finger_x) {
    a.dock({x, main_y + dir * (1.25 + 0.5 * len)}, {1.5, len}, 0.0);
    for (double side : {-1.0, 1.0}) {
      a.piling(x + side * 1.0 + rng.uniform(-0.1, 0.1), finger_end_y - dir * 0.3 + rng.uniform(-0.1, 0.1),
               rng.uniform(0.15, 0.21));
    }
    a.piling(x + 1.0, main_y + dir * (1.25 + 0.5 * len), rng.uniform(0.15, 0.2));
  }
}

// Pilings along both long sides of a dock running along x at y.
void dock_pilings(SceneAssembly& a, Rng& rng, double x0, double x1, double y, double half_width,
                  double spacing) {
  for (double x = x0; x <= x1 + 1e-9; x += spacing) {
    for (double side : {-1.0, 1.0}) {
      a.piling(x + rng.uniform(-0.2, 0.2), y + side * (half_width + 0.25), rng.uniform(0.15, 0.22));
    }
  }
}

// A small motor boat moored with its bow towards +y (or -y), class boat.
void small_boat(SceneAssembly& a, Rng& rng, const Vec2& c, double yaw) {
  HullShape s;
  s.length_m = rng.uniform(6.5, 9.0);
  s.beam_m = rng.uniform(2.4, 3.0);
  s.draft_m = rng.uniform(0.7, 1.0);
  s.freeboard_m = 1.0;
  s.fullness = 1.6;
  s.stern_width_fraction = 0.85;
  s.bow_start_fraction = 0.55;
  s.stations = 16;
  s.section_points = 10;
  const Label l = a.next(SemanticClass::kBoat);
  const SE3 T = se3_from_xyz_rpy(c.x(), c.y(), 0.0, 0.0, 0.0, yaw);
  hull(a.b, s, T, l);
  const size_t first = a.scene.mesh.vertices.size();
  a.b.box({-0.1 * s.length_m, 0.0, s.freeboard_m + 0.6}, {0.35 * s.length_m, 0.7 * s.beam_m, 1.2}, 0.0, l);
  transform_tail(a.scene.mesh, first, T);
}

}  // namespace

Scene build_marina1(uint64_t seed) {
  SceneAssembly a;
  a.scene.seed = seed;
  a.scene.vehicle_depth_m = 3.0;
  a.scene.seafloor_depth_m = 8.0;
  // Two lanes 3.75 m off the breakwater's piling rows (y = +-1.75), closed by turns round
  // its heads (one lap ~ 190 m). That close, the row ahead stays inside the +-10 deg
  // overlap from ~21 m out, so the vertical sonar sees the pilings the horizontal one
  // classifies (docs/SCENES.md). Starts 55 m before the east turn, with the north row ahead.
  a.scene.route = {{-15, 5.5}, {40, 5.5}, {45, 0}, {40, -5.5}, {-40, -5.5}, {-45, 0}, {-40, 5.5}, {-15, 5.5}};
  a.seafloor(-65, 65, -50, 50, 0.4);
  Rng rng(derive_seed(seed, 0x4d41524931ull));
  const std::vector<double> fingers = {-30, -20, -10, 0, 10, 20, 30};
  // North main dock with fingers to y = 16; south main dock with fingers to y = -16.
  a.dock({0, 30}, {84, 2.5}, 0.0);
  dock_pilings(a, rng, -40, 40, 30, 1.25, 8.0);
  finger_row(a, rng, 30, 16, fingers);
  a.dock({0, -30}, {84, 2.5}, 0.0);
  dock_pilings(a, rng, -40, 40, -30, 1.25, 8.0);
  finger_row(a, rng, -30, -16, fingers);
  // Central breakwater dock, pilings every 7 m on both sides.
  a.dock({0, 0}, {70, 3.0}, 0.0);
  dock_pilings(a, rng, -35, 35, 0, 1.5, 7.0);
  a.debris(30, -60, 60, -45, 45, 3.0, 0x4445425249ull);
  return std::move(a.scene);
}

Scene build_marina2(uint64_t seed) {
  SceneAssembly a;
  a.scene.seed = seed;
  a.scene.vehicle_depth_m = 2.5;
  a.scene.seafloor_depth_m = 7.0;
  // Along the dolphins, up the east side, along the seawall, down the west wall.
  // Starts 22 m before the east turn, so even a one-minute mission sees the east end head-on.
  a.scene.route = {{20, 4}, {42, 4}, {47, 18}, {42, 29}, {-40, 29}, {-47, 18}, {-45, 4}, {20, 4}};
  a.seafloor(-70, 70, -25, 37, 0.3);
  Rng rng(derive_seed(seed, 0x4d41524932ull));
  // Corrugated sheet-pile seawall along y = 36 and a return wall along x = -55, with cap beams.
  a.b.corrugated_wall({-65, 36}, {65, 36}, -7.8, 1.5, 1.4, 0.35, a.next(SemanticClass::kSeawall));
  a.b.box({0, 36.5, 1.2}, {130, 1.0, 0.6}, 0.0, a.next(SemanticClass::kSeawall));
  a.b.corrugated_wall({-55, 8}, {-55, 36}, -7.8, 1.5, 1.4, -0.35, a.next(SemanticClass::kSeawall));
  // Main dock at y = 22 with fingers to y = 10 and boats in most slips.
  const std::vector<double> fingers = {-30, -18, -6, 6, 18, 30};
  a.dock({0, 22}, {72, 2.5}, 0.0);
  dock_pilings(a, rng, -34, 34, 22, 1.25, 8.5);
  finger_row(a, rng, 22, 10, fingers);
  for (double x = -24; x <= 24; x += 12) {
    for (double side : {-1.0, 1.0}) {
      if (rng.uniform() < 0.25) continue;  // an empty slip
      small_boat(a, rng, {x + side * 2.8, 15.5}, side > 0 ? std::numbers::pi / 2 : -std::numbers::pi / 2);
    }
  }
  // Mooring dolphins (three pilings each) along y = -6.
  for (double x = -40; x <= 40; x += 13.3) {
    for (int k = 0; k < 3; ++k) {
      const double ang = 2.0 * std::numbers::pi * k / 3.0;
      a.piling(x + 0.6 * std::cos(ang), -6 + 0.6 * std::sin(ang), rng.uniform(0.17, 0.22));
    }
  }
  a.debris(30, -65, 65, -20, 34, 3.0, 0x4445425249ull);
  return std::move(a.scene);
}

}  // namespace orthosonar::sim::detail
