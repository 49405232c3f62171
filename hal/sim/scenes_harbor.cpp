// harbor and aircraft (docs/SCENES.md): large unique structures, few repeating objects.
#include <cmath>
#include <numbers>

#include "hal/sim/scenes_builtin.hpp"
#include "core/geometry.hpp"

namespace orthosonar::sim::detail {
namespace {

// A three-masted sailing ship (about 40 m, beam 9 m, draft 4 m) with a full keel and rudder.
void sailing_ship(SceneAssembly& a, const SE3& T) {
  HullShape s;
  s.length_m = 40.0;
  s.beam_m = 9.0;
  s.draft_m = 4.0;
  s.freeboard_m = 3.0;
  s.fullness = 2.6;
  s.stern_width_fraction = 0.7;
  s.bow_start_fraction = 0.55;
  s.bow_rake_m = -2.0;  // a clipper bow: the stem rakes forward above the keel
  const Label l = a.next(SemanticClass::kHull);
  hull(a.b, s, T, l);
  const size_t first = a.scene.mesh.vertices.size();
  a.b.box({0.0, 0.0, -4.35}, {32.0, 0.5, 0.7}, 0.0, l);      // keel
  a.b.box({-20.3, 0.0, -2.0}, {1.6, 0.3, 3.6}, 0.0, l);      // rudder
  a.b.cylinder({21.0, 0, 2.5}, {29.0, 0, 5.0}, 0.25, 8, l);  // bowsprit
  for (double x : {-10.0, 2.0, 13.0}) a.b.cylinder({x, 0, 3.0}, {x, 0, 28.0}, 0.35, 10, l);  // masts
  transform_tail(a.scene.mesh, first, T);
}

// An early-20th-century protected cruiser (about 100 m, beam 16 m, draft 6.5 m) with a ram
// bow, bilge keels, twin shafts and screws, three funnels and two turrets.
void cruiser(SceneAssembly& a, const SE3& T) {
  HullShape s;
  s.length_m = 100.0;
  s.beam_m = 16.0;
  s.draft_m = 6.5;
  s.freeboard_m = 5.5;
  s.fullness = 3.2;
  s.stern_width_fraction = 0.6;
  s.bow_start_fraction = 0.62;
  s.bow_rake_m = 3.0;  // ram bow
  s.stations = 60;
  s.section_points = 20;
  const Label l = a.next(SemanticClass::kHull);
  hull(a.b, s, T, l);
  const size_t first = a.scene.mesh.vertices.size();
  for (double side : {-1.0, 1.0}) {
    a.b.box({0.0, side * 7.2, -5.4}, {40.0, 0.25, 0.9}, side * 35.0 * kRadPerDeg, l);  // bilge keels (approx.)
    a.b.cylinder({-38.0, side * 3.2, -4.8}, {-50.5, side * 3.2, -4.6}, 0.35, 10, l);  // shaft
    for (int blade = 0; blade < 3; ++blade) {
      const double ang = blade * 2.0 * std::numbers::pi / 3.0;
      a.b.box({-49.5, side * 3.2 + 0.9 * std::cos(ang), -4.6 + 0.9 * std::sin(ang)}, {0.3, 0.5, 1.8}, 0.0, l);
    }
  }
  a.b.box({-49.0, 0.0, -3.3}, {3.0, 0.4, 4.4}, 0.0, l);  // rudder
  a.b.box({5.0, 0.0, 7.5}, {40.0, 10.0, 4.0}, 0.0, l);   // superstructure
  for (double x : {-6.0, 6.0, 18.0}) a.b.cylinder({x, 0, 9.0}, {x, 0, 20.0}, 1.6, 14, l);  // funnels
  for (double x : {-35.0, 38.0}) a.b.cylinder({x, 0, 5.5}, {x, 0, 8.0}, 3.2, 16, l);      // turrets
  transform_tail(a.scene.mesh, first, T);
}

// A four-engine bomber with a twin tail (B-24 class: 20.6 m long, 33.5 m span), built in
// its own frame (x forward, belly at z = 0) and then placed.
void bomber(SceneAssembly& a, const SE3& T) {
  const Label l = a.next(SemanticClass::kAircraft);
  const size_t first = a.scene.mesh.vertices.size();
  // Fuselage: elliptical sections, deep and narrow, tapering to the nose and the tail.
  std::vector<std::vector<Vec3>> rings;
  for (int i = 0; i <= 30; ++i) {
    const double u = i / 30.0;  // 0 tail .. 1 nose
    const double x = -10.2 + 20.6 * u;
    double scale = 1.0;
    if (u < 0.45) scale = 0.18 + 0.82 * std::sqrt(u / 0.45);
    if (u > 0.85) scale = std::sqrt(std::max(0.02, 1.0 - std::pow((u - 0.85) / 0.15, 2.0)));
    const double hw = 1.05 * scale, hh = 1.4 * scale;
    const double zc = 1.4 + (u < 0.45 ? 0.9 * (1.0 - scale) : 0.0);  // tail boom rises
    std::vector<Vec3> ring;
    for (int k = 0; k < 16; ++k) {
      const double t = 2.0 * std::numbers::pi * k / 16;
      ring.emplace_back(x, hw * std::cos(t), zc + hh * std::sin(t));
    }
    rings.push_back(ring);
  }
  a.b.loft(rings, true, true, l);
  // Shoulder wing: lens-shaped sections from root (chord 4.6 m) to tip (1.6 m), slight dihedral.
  for (double side : {-1.0, 1.0}) {
    std::vector<std::vector<Vec3>> wing;
    for (int i = 0; i <= 8; ++i) {
      const double f = i / 8.0;
      const double y = side * (1.0 + 15.75 * f);
      const double chord = 4.6 - 3.0 * f, thick = 0.65 - 0.45 * f;
      const double xle = 2.6 - 1.2 * f, z = 2.4 + 0.5 * f;
      wing.push_back({{xle, y, z}, {xle - 0.3 * chord, y, z + 0.5 * thick}, {xle - chord, y, z + 0.03},
                      {xle - 0.3 * chord, y, z - 0.5 * thick}});
    }
    a.b.loft(wing, true, true, l);
    for (double span : {4.6, 9.2}) {  // engine nacelles and propellers
      const double y = side * span, z = 2.15 + 0.5 * span / 15.75;
      a.b.cylinder({4.6, y, z}, {-1.8, y, z}, 0.62, 12, l);
      a.b.box({4.75, y, z}, {0.15, 0.25, 3.4}, 0.3, l);
    }
  }
  a.b.box({-8.4, 0.0, 2.3}, {1.9, 8.6, 0.22}, 0.0, l);  // horizontal stabiliser
  for (double side : {-1.0, 1.0}) {
    std::vector<std::vector<Vec3>> fin;  // oval twin fins
    for (int i = 0; i <= 6; ++i) {
      const double z = 1.0 + 3.4 * i / 6.0;
      const double half = 1.1 * std::sqrt(std::max(0.05, 1.0 - std::pow((z - 2.7) / 1.75, 2.0)));
      fin.push_back({{-8.4 + half, side * 4.3 - 0.13, z}, {-8.4 + half, side * 4.3 + 0.13, z},
                     {-8.4 - half, side * 4.3 + 0.13, z}, {-8.4 - half, side * 4.3 - 0.13, z}});
    }
    a.b.loft(fin, true, true, l);
  }
  transform_tail(a.scene.mesh, first, T);
}

}  // namespace

// The demo's survey (issue 38): the pair fuses only what lies ahead, within the ±10° the two
// apertures share, so this route keeps structure ahead. A sawtooth along the sailing ship's
// side (each north-east leg runs at the hull), then at the pier's pilings, north at the quay
// wall, round the pier head at the cruiser's end and north again at the quay between pier and
// cruiser; home along the outer side.
std::vector<Waypoint> harbor_survey_route() {
  return {{-60, -32}, {-54, -21}, {-49, -29}, {-43, -20}, {-38, -28}, {-32, -20}, {-27, -28}, {-21, -19}, {-14, -14},
          {-13, -6},  {-14, -22}, {-8, -37},  {2, -31},   {3, -12},   {5, -30},   {-20, -42}, {-60, -42}};
}

Scene build_harbor(uint64_t seed) {
  SceneAssembly a;
  a.scene.seed = seed;
  a.scene.vehicle_depth_m = 3.0;
  a.scene.seafloor_depth_m = 10.0;
  // Along the sailing ship, round the pier head, along the cruiser, back farther out, home.
  // Starts 30 m along the first leg, where the docks come into the overlap within seconds.
  a.scene.route = {{-45, -24}, {-20, -24}, {-12, -37}, {5, -38},   {60, -34}, {100, -34}, {116, -45},
                   {60, -49},  {5, -47},   {-14, -44}, {-32, -31}, {-70, -31}, {-75, -24}, {-45, -24}};
  a.seafloor(-130, 160, -85, 1, 0.5);
  Rng rng(derive_seed(seed, 0x484152424full));
  // The long quay: corrugated sheet piling along y = 0 with a concrete cap.
  a.b.corrugated_wall({-120, 0.4}, {150, 0.4}, -11.0, 2.0, 1.6, 0.4, a.next(SemanticClass::kSeawall));
  a.b.box({15, 1.2, 1.7}, {270, 1.6, 0.6}, 0.0, a.next(SemanticClass::kSeawall));
  // Moored alongside the quay: the sailing ship (bow east) and the cruiser (bow west).
  sailing_ship(a, se3_from_xyz_rpy(-42 + rng.uniform(-0.5, 0.5), -9.5, 0.0, 1.0 * kRadPerDeg, 0.0, rng.uniform(-0.02, 0.02)));
  cruiser(a, se3_from_xyz_rpy(60 + rng.uniform(-0.5, 0.5), -15.5, 0.0, -0.5 * kRadPerDeg, 0.0, std::numbers::pi + rng.uniform(-0.01, 0.01)));
  // A floating pier off the quay at x = -5, to y = -30, on pilings every 6 m.
  a.dock({-5, -15}, {3.0, 29.5}, 0.0);
  for (double y = -4; y >= -30; y -= 6.0) {
    for (double side : {-1.0, 1.0}) a.piling(-5 + side * 1.8, y + rng.uniform(-0.2, 0.2), rng.uniform(0.22, 0.28));
  }
  // A short float along the quay at the east end, and two mooring dolphins.
  a.dock({135, -3.0}, {20, 2.5}, 0.0);
  for (double x : {128.0, 142.0}) a.piling(x, -4.6, 0.25);
  for (const Vec2& c : {Vec2(-95, -20), Vec2(130, -30)}) {
    for (int k = 0; k < 4; ++k) a.piling(c.x() + (k % 2) * 0.9, c.y() + (k / 2) * 0.9, 0.25);
  }
  // Concrete mooring blocks and debris on the bottom.
  for (int k = 0; k < 6; ++k) {
    const double x = -110 + 45 * k + rng.uniform(-5, 5), y = rng.uniform(-75, -55);
    a.b.box({x, y, a.floor_z(x, y) + 0.4}, {2.0, 2.0, 1.2}, rng.uniform(0, 1.5), a.next(SemanticClass::kOther));
  }
  a.debris(40, -125, 155, -80, -3, 3.0, 0x4445425249ull);
  return std::move(a.scene);
}

Scene build_aircraft(uint64_t seed) {
  SceneAssembly a;
  a.scene.seed = seed;
  a.scene.vehicle_depth_m = 3.0;
  a.scene.seafloor_depth_m = 7.0;
  // Four approach legs aimed at the aircraft (from the west, south, east and north), each
  // from 34 m out to 18 m from its centre, joined by diagonal exits. A forward-looking
  // pair sees an object in its +-10 deg overlap only while heading at it, so an orbit
  // (the aircraft abeam, outside the 130 deg fan) would give fusion almost nothing. The
  // approaches stop short of the wing tips (|y| <= 15.5 m) and of the tail fins, which
  // rise above the vehicle's 3 m depth.
  a.scene.route = {{-34, 0}, {-18, 0}, {0, -34}, {0, -18}, {34, 0}, {18, 0}, {0, 34}, {0, 19}, {-34, 0}};
  a.seafloor(-75, 75, -75, 75, 0.25);
  Rng rng(derive_seed(seed, 0x4149524352ull));
  const double yaw = 25.0 * kRadPerDeg + rng.uniform(-0.05, 0.05);
  const double z0 = a.floor_z(0.0, 0.0) - 0.35;  // settled into the sediment
  bomber(a, se3_from_xyz_rpy(0.0, 0.0, z0, 3.0 * kRadPerDeg, -1.5 * kRadPerDeg, yaw));
  a.debris(20, -70, 70, -70, 70, 3.0, 0x4445425249ull);
  return std::move(a.scene);
}

}  // namespace orthosonar::sim::detail
