#pragma once
// Scenes for the simulator (SPEC §10): a labelled triangle mesh (object id and semantic
// class per triangle, world frame W, metres, z up, z = 0 at the water surface), a default
// waypoint route and the working depths. Built-in scenes are pure functions of
// (name, seed); user scenes come from a YAML file that places mesh files. Fixtures embed
// their scene (embed_scene / scene_from_fixture), so replay never needs the YAML's path.
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

// A route a scene offers besides its default one (SimConfig::route picks it).
struct NamedRoute {
  std::string name;
  std::vector<Waypoint> waypoints;
};

struct Scene {
  std::string name;                 // "harbor", or the YAML's name
  uint64_t seed = 0;                // geometry seed (jitter, seafloor relief, clutter)
  TriangleMesh mesh;                // W frame, z up, surface at z = 0
  std::vector<Waypoint> route;      // the route flown, at vehicle depth; followed cyclically
  std::string route_name = "default";  // which route `route` is (select_route)
  std::vector<NamedRoute> routes;   // the scene's other routes (built-in: harbor's "survey")
  double vehicle_depth_m = 3.0;     // positive down
  double seafloor_depth_m = 9.0;    // nominal, positive down
  // Where on Earth (degrees north): the Earth rate a fibre-optic gyro senses, sin(latitude)
  // of it about the vertical. Default the authors' 40.706 (paper §VI, their gyro node).
  double latitude_deg = 40.706;
  // Where the scene came from: the built-in name or "file:<absolute yaml path>" (fixture
  // metadata records portable_origin(), without the folder); for a scene rebuilt from a
  // fixture's embedded files, the origin recorded there.
  std::string origin;
};

// Makes the scene fly `name`'s route: "" or "default" keeps its own; another name must be
// one of scene.routes (the error lists the names there are).
Status select_route(Scene& scene, const std::string& name);

// The named routes of a built-in scene (harbor: "survey"), or of all of them with `scene`
// empty, without building a scene: the demo's choice and the `route` key's valid names.
std::vector<std::string> builtin_route_names(const std::string& scene = "");

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
// A "file:" entry without a folder (fixtures since scenes are embedded) is an error here:
// such fixtures carry their scene, see scene_from_fixture.
Result<Scene> scene_from_metadata(const std::map<std::string, std::string>& fixture_metadata);

// What fixture metadata calls `scene` without depending on where its files live: the
// built-in name, or "file:<yaml file name>" for a user scene.
std::string portable_origin(const Scene& scene);

// ---- Scenes embedded in fixtures (MCAP attachments; docs/SCENES.md)
// The mesh as binary PLY (write_mesh_ply: float vertices, per-face object_id and semantic)
// and a scene YAML in the user-scene format that places that mesh with `class: from_file`
// and lists name, seed, depths, route and the class table. Together they are a scene file.
inline constexpr const char* kEmbeddedSceneYaml = "orthosonar_scene.yaml";
inline constexpr const char* kEmbeddedSceneYamlType = "application/yaml";
inline constexpr const char* kEmbeddedSceneMesh = "orthosonar_scene.ply";
inline constexpr const char* kEmbeddedSceneMeshType = "application/x-ply";

struct EmbeddedFile {
  std::string name;
  std::string media_type;
  std::vector<uint8_t> data;
};
// Name -> bytes of the files embedded in a fixture (replay::attachment_files).
using EmbeddedFiles = std::map<std::string, std::vector<uint8_t>>;

// The files that describe `scene` (deterministic bytes, no paths): YAML first, then mesh.
Result<std::vector<EmbeddedFile>> embed_scene(const Scene& scene);
bool has_embedded_scene(const EmbeddedFiles& files);
// The scene embed_scene wrote: bit-identical mesh, route and depths; origin as recorded.
// Errors name the attachment at fault.
Result<Scene> scene_from_embedded(const EmbeddedFiles& files);
// A fixture's scene: the embedded one when the fixture has it, else (fixtures written
// before scenes were embedded) scene_from_metadata. `embedded` (optional) says which.
Result<Scene> scene_from_fixture(const std::map<std::string, std::string>& fixture_metadata,
                                 const EmbeddedFiles& files, bool* embedded = nullptr);

}  // namespace orthosonar::sim
