#pragma once
// The built-in scenes (private to hal/sim): see docs/SCENES.md for layouts and routes.
#include <cstdint>

#include "hal/sim/primitives.hpp"
#include "hal/sim/scene.hpp"

namespace orthosonar::sim::detail {

// Hands out object ids (1 = seafloor) and keeps the mesh being built.
struct SceneAssembly {
  Scene scene;
  MeshBuilder b{scene.mesh};
  uint32_t next_id = 1;
  Label next(SemanticClass c) { return {next_id++, c}; }
  // A seafloor height field covering [x0, x1] x [y0, y1] with 1 m cells.
  void seafloor(double x0, double x1, double y0, double y1, double relief_m);
  // A round piling from below the seafloor to above the surface.
  void piling(double x, double y, double radius_m);
  // A floating dock (pontoon) box from z = -draft to z = +freeboard.
  void dock(const Vec2& center, const Vec2& size, double yaw, double draft_m = 0.5);
  // Scattered rocks/debris (class other) in a box, away from the route by min_clear_m.
  void debris(int count, double x0, double x1, double y0, double y1, double min_clear_m, uint64_t stream);
  std::function<double(double, double)> floor_z;
};

Scene build_marina1(uint64_t seed);
Scene build_marina2(uint64_t seed);
Scene build_harbor(uint64_t seed);
std::vector<Waypoint> harbor_survey_route();  // the harbor's "survey" (builtin_route_names)
Scene build_aircraft(uint64_t seed);

}  // namespace orthosonar::sim::detail
