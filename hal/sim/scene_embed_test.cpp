// Scenes embedded in fixtures: embed_scene's files rebuild the exact scene (mesh, route,
// depths), with no path anywhere, and old fixtures fall back to their metadata.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"

namespace orthosonar::sim {
namespace {

namespace fs = std::filesystem;

fs::path embed_out_dir(const std::string& name) {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = fs::path(env ? env : fs::temp_directory_path().string()) / "sim_scene_embed" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

EmbeddedFiles as_files(const std::vector<EmbeddedFile>& v) {
  EmbeddedFiles out;
  for (const auto& f : v) out[f.name] = f.data;
  return out;
}

void check_same(const Scene& a, const Scene& b) {
  CHECK(a.name == b.name);
  CHECK(a.seed == b.seed);
  CHECK(a.mesh.vertices == b.mesh.vertices);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  CHECK(a.mesh.object_id == b.mesh.object_id);
  CHECK(a.mesh.semantic == b.mesh.semantic);
  CHECK(a.route == b.route);
  CHECK(a.vehicle_depth_m == b.vehicle_depth_m);
  CHECK(a.seafloor_depth_m == b.seafloor_depth_m);
}

// A small user scene in `dir`: an OBJ placed with a pose, a generated seafloor and a route
// file whose coordinates need all 17 digits.
void write_site(const fs::path& dir) {
  TriangleMesh tri;
  tri.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tri.triangles = {{0, 1, 2}, {0, 1, 3}};
  tri.object_id = {1, 1};
  tri.semantic = {SemanticClass::kOther, SemanticClass::kOther};
  REQUIRE(write_mesh_obj(tri, (dir / "thing.obj").string()).ok());
  std::ofstream(dir / "route.csv") << "# x, y\n0.1, 0.2\n10.333333333333334, -1e-7\n-3.14159, 2.718281828459045\n";
  std::ofstream(dir / "site.yaml") << "name: my \"site\"\nseed: 4\nvehicle_depth_m: 2.7\nseafloor_depth_m: 6.1\n"
                                      "seafloor: {x_min_m: -8, x_max_m: 8, y_min_m: -6, y_max_m: 6, relief_m: 0.2}\n"
                                      "objects:\n  - mesh: thing.obj\n    class: hull\n    pose: [1, 2, -3, 5, 10, 33]\n"
                                      "route_file: route.csv\n";
}

}  // namespace

TEST_CASE("embedded scene: a built-in scene round-trips bit-identically", "[hal][embed]") {
  const auto scene = builtin_scene("marina2", 3);
  REQUIRE(scene.ok());
  auto files = embed_scene(*scene);
  REQUIRE(files.ok());
  REQUIRE(files->size() == 2);
  CHECK((*files)[0].name == kEmbeddedSceneYaml);
  CHECK((*files)[0].media_type == std::string("application/yaml"));
  CHECK((*files)[1].name == kEmbeddedSceneMesh);
  CHECK((*files)[1].media_type == std::string("application/x-ply"));
  auto again = embed_scene(*scene);
  REQUIRE(again.ok());
  CHECK(as_files(*again) == as_files(*files));  // deterministic bytes
  auto back = scene_from_embedded(as_files(*files));
  REQUIRE(back.ok());
  check_same(*back, *scene);
  CHECK(back->origin == "marina2");
  bool embedded = false;
  auto via_fixture = scene_from_fixture({{"scene", "harbor"}}, as_files(*files), &embedded);
  REQUIRE(via_fixture.ok());
  CHECK(embedded);  // the embedded scene wins over the metadata
  CHECK(via_fixture->name == "marina2");
}

TEST_CASE("embedded scene: a user scene needs no file once embedded", "[hal][embed]") {
  const auto dir = embed_out_dir("site");
  write_site(dir);
  auto scene = load_scene_file((dir / "site.yaml").string());
  REQUIRE(scene.ok());
  CHECK(scene->origin == "file:" + (dir / "site.yaml").string());
  CHECK(portable_origin(*scene) == "file:site.yaml");
  auto files = embed_scene(*scene);
  REQUIRE(files.ok());
  const auto yaml = std::string((*files)[0].data.begin(), (*files)[0].data.end());
  CHECK(yaml.find(dir.string()) == std::string::npos);  // no path in the embedded files
  CHECK(yaml.find("origin: \"file:site.yaml\"") != std::string::npos);

  // The same scene from another folder embeds the same bytes.
  const auto other = embed_out_dir("elsewhere");
  write_site(other);
  auto moved = load_scene_file((other / "site.yaml").string());
  REQUIRE(moved.ok());
  auto moved_files = embed_scene(*moved);
  REQUIRE(moved_files.ok());
  CHECK(as_files(*moved_files) == as_files(*files));

  fs::remove_all(dir);
  fs::remove_all(other);
  const std::map<std::string, std::string> md{{"scene", "file:site.yaml"}, {"scene_seed", "4"}};
  auto back = scene_from_fixture(md, as_files(*files));
  REQUIRE(back.ok());
  check_same(*back, *scene);
  CHECK(back->origin == "file:site.yaml");

  // Saved beside its mesh, the embedded YAML is a scene file.
  const auto extracted = embed_out_dir("extracted");
  for (const auto& f : *files)
    std::ofstream(extracted / f.name, std::ios::binary)
        .write(reinterpret_cast<const char*>(f.data.data()), static_cast<std::streamsize>(f.data.size()));
  auto loaded = load_scene_file((extracted / kEmbeddedSceneYaml).string());
  REQUIRE(loaded.ok());
  check_same(*loaded, *scene);

  // Without the embedded files, a folder-less metadata entry is a clear error.
  auto none = scene_from_fixture(md, {});
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().message.find("without its folder") != std::string::npos);
}

TEST_CASE("embedded scene: old fixtures fall back to the metadata", "[hal][embed]") {
  bool embedded = true;
  auto builtin = scene_from_fixture({{"scene", "marina1"}, {"scene_seed", "2"}}, {}, &embedded);
  REQUIRE(builtin.ok());
  CHECK_FALSE(embedded);
  check_same(*builtin, *builtin_scene("marina1", 2));
  // A --scene-file fixture whose file is gone: an error naming it, no crash.
  auto gone = scene_from_fixture({{"scene", "file:/nonexistent/orthosonar/site.yaml"}}, {});
  REQUIRE_FALSE(gone.ok());
  CHECK(gone.error().message.find("/nonexistent/orthosonar/site.yaml") != std::string::npos);
}

TEST_CASE("embedded scene: damaged files are named", "[hal][embed]") {
  auto scene = builtin_scene("aircraft", 1);
  REQUIRE(scene.ok());
  auto files = embed_scene(*scene);
  REQUIRE(files.ok());
  auto f = as_files(*files);
  auto cut = f;
  cut[kEmbeddedSceneMesh].resize(cut[kEmbeddedSceneMesh].size() / 2);
  auto r = scene_from_embedded(cut);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find(std::string("attachment '") + kEmbeddedSceneMesh + "'") != std::string::npos);
  auto no_mesh = f;
  no_mesh.erase(kEmbeddedSceneMesh);
  r = scene_from_embedded(no_mesh);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("not embedded") != std::string::npos);
  auto bad_yaml = f;
  const std::string junk = "route: [[0, 0], [1";
  bad_yaml[kEmbeddedSceneYaml].assign(junk.begin(), junk.end());
  r = scene_from_embedded(bad_yaml);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find(kEmbeddedSceneYaml) != std::string::npos);
}

}  // namespace orthosonar::sim
