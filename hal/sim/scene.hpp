#pragma once
// Scenes for the simulator (SPEC §10): a labelled triangle mesh (object id and semantic
// class per triangle, world frame W, metres, z up, z = 0 at the water surface), a default
// waypoint route and the working depths. Built-in scenes are pure functions of
// (name, seed); user scenes come from a YAML file that places mesh files.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/mesh.hpp"
#include "core/result.hpp"

namespace orthosonar::sim {

struct Waypoint {
  double x_m = 0.0;
  double y_m = 0.0;
  friend bool operator==(const Waypoint&, const Waypoint&) = default;
};

struct Scene {
  std::string name;                 // "harbor", or the YAML's name
  uint64_t seed = 0;                // geometry seed (jitter, seafloor relief, clutter)
  TriangleMesh mesh;                // W frame, z up, surface at z = 0
  std::vector<Waypoint> route;      // default route at vehicle depth; followed cyclically
  double vehicle_depth_m = 3.0;     // positive down
  double seafloor_depth_m = 9.0;    // nominal, positive down
  // What fixture metadata calls the scene: the built-in name or "file:<yaml path>".
  std::string origin;
};

// The built-in scenes in a fixed order: marina1, marina2, harbor, aircraft.
std::vector<std::string> builtin_scene_names();
// A built-in scene; the same (name, seed) gives a bit-identical mesh. Unknown names are errors.
Result<Scene> builtin_scene(const std::string& name, uint64_t seed);

// A user scene from YAML (see docs/SCENES.md): mesh files (PLY/OBJ/STL) with poses,
// scale and classes, an optional generated seafloor, and a route (inline or a CSV file).
// Relative mesh and route paths are resolved against the YAML's folder.
Result<Scene> load_scene_file(const std::string& yaml_path);

// Rebuilds the exact scene a fixture was simulated with, from its metadata
// ("scene" = built-in name or "file:<path>", "scene_seed" or else "seed").
Result<Scene> scene_from_metadata(const std::map<std::string, std::string>& fixture_metadata);

}  // namespace orthosonar::sim
