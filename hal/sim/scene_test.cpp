#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::sim {
namespace {

std::filesystem::path scene_out_dir() {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = std::filesystem::path(env ? env : std::filesystem::temp_directory_path().string()) / "sim_scene";
  std::filesystem::create_directories(dir);
  return dir;
}

// Does some triangle of class c span depth z (world z = -depth)?
bool spans_depth(const TriangleMesh& m, SemanticClass c, double depth) {
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    if (m.semantic[i] != c) continue;
    float lo = 1e9f, hi = -1e9f;
    for (int k = 0; k < 3; ++k) {
      lo = std::min(lo, m.vertices[static_cast<size_t>(m.triangles[i][k])].z());
      hi = std::max(hi, m.vertices[static_cast<size_t>(m.triangles[i][k])].z());
    }
    if (lo <= -depth && hi >= -depth) return true;
  }
  return false;
}

}  // namespace

TEST_CASE("built-in scenes are valid deterministic and realistic", "[hal]") {
  REQUIRE(builtin_scene_names() == std::vector<std::string>{"marina1", "marina2", "harbor", "aircraft"});
  for (const auto& name : builtin_scene_names()) {
    INFO(name);
    auto a = builtin_scene(name, 1);
    auto b = builtin_scene(name, 1);
    auto c = builtin_scene(name, 2);
    REQUIRE(a.ok());
    CHECK(a->mesh.valid());
    CHECK(a->mesh.vertices == b->mesh.vertices);
    CHECK(a->mesh.object_id == b->mesh.object_id);
    CHECK(a->mesh.vertices != c->mesh.vertices);
    CHECK(a->seafloor_depth_m >= 6.0);
    CHECK(a->seafloor_depth_m <= 12.0);
    CHECK(a->vehicle_depth_m >= 2.0);
    CHECK(a->vehicle_depth_m <= 4.0);
    CHECK(a->route.size() >= 4u);
    CHECK(a->route.front() == a->route.back());  // the route closes a loop
    CHECK(a->origin == name);
    CHECK(spans_depth(a->mesh, SemanticClass::kSeafloor, a->seafloor_depth_m));
  }
  // Structures span the horizontal sonar's depth.
  CHECK(spans_depth(builtin_scene("marina1", 1)->mesh, SemanticClass::kPiling, 3.0));
  CHECK(spans_depth(builtin_scene("marina2", 1)->mesh, SemanticClass::kSeawall, 2.5));
  CHECK(spans_depth(builtin_scene("marina2", 1)->mesh, SemanticClass::kBoat, 0.5));
  CHECK(spans_depth(builtin_scene("harbor", 1)->mesh, SemanticClass::kHull, 3.0));
  CHECK(spans_depth(builtin_scene("harbor", 1)->mesh, SemanticClass::kSeawall, 3.0));
  CHECK(spans_depth(builtin_scene("aircraft", 1)->mesh, SemanticClass::kAircraft, 5.5));
  CHECK(!builtin_scene("atlantis", 1).ok());
}

TEST_CASE("a scene file equal to a built-in loads the same scene", "[hal]") {
  const auto harbor = builtin_scene("marina1", 3);
  REQUIRE(harbor.ok());
  const auto dir = scene_out_dir();
  REQUIRE(write_mesh_ply(harbor->mesh, (dir / "marina1.ply").string()).ok());
  {
    std::ofstream route(dir / "route.csv");
    route << "# x, y\n";
    for (const auto& w : harbor->route) route << w.x_m << ", " << w.y_m << "\n";
  }
  std::ofstream(dir / "site.yaml") << "name: marina1\nseed: 3\nvehicle_depth_m: 3\nseafloor_depth_m: 8\n"
                                      "objects:\n  - mesh: marina1.ply\n    class: from_file\nroute_file: route.csv\n";
  auto s = load_scene_file((dir / "site.yaml").string());
  REQUIRE(s.ok());
  CHECK(s->mesh.vertices == harbor->mesh.vertices);
  CHECK(s->mesh.triangles == harbor->mesh.triangles);
  CHECK(s->mesh.object_id == harbor->mesh.object_id);
  CHECK(s->mesh.semantic == harbor->mesh.semantic);
  CHECK(s->route == harbor->route);
  CHECK(s->vehicle_depth_m == harbor->vehicle_depth_m);
  CHECK(s->origin.rfind("file:", 0) == 0);
  // The metadata names the scene so tools can rebuild it.
  auto again = scene_from_metadata({{"scene", s->origin}, {"seed", "99"}});
  REQUIRE(again.ok());
  CHECK(again->mesh.vertices == harbor->mesh.vertices);
  auto builtin = scene_from_metadata({{"scene", "marina1"}, {"seed", "99"}, {"scene_seed", "3"}});
  REQUIRE(builtin.ok());
  CHECK(builtin->mesh.vertices == harbor->mesh.vertices);
}

TEST_CASE("scene files place meshes with poses and classes and report errors", "[hal]") {
  const auto dir = scene_out_dir();
  TriangleMesh cube;
  cube.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  cube.triangles = {{0, 1, 2}};
  cube.object_id = {1};
  cube.semantic = {SemanticClass::kOther};
  REQUIRE(write_mesh_obj(cube, (dir / "tri.obj").string()).ok());
  std::ofstream(dir / "placed.yaml") << "name: placed\nseafloor_depth_m: 6\n"
                                        "seafloor: {x_min_m: -5, x_max_m: 5, y_min_m: -5, y_max_m: 5}\n"
                                        "objects:\n  - mesh: tri.obj\n    class: piling\n    pose: [10, 0, -2, 0, 0, 90]\n"
                                        "    scale: 2\nroute: [[0, 0], [10, 0]]\n";
  auto s = load_scene_file((dir / "placed.yaml").string());
  REQUIRE(s.ok());
  CHECK(s->mesh.triangles.size() == 201u);  // 10 x 10 cells x 2 + 1
  CHECK(s->mesh.semantic.back() == SemanticClass::kPiling);
  CHECK(s->mesh.object_id.back() == 2u);
  const Eigen::Vector3f p = s->mesh.vertices[s->mesh.vertices.size() - 2];  // (2, 0, 0) rotated 90 deg
  CHECK(p.x() == Approx(10.0f).margin(1e-5));
  CHECK(p.y() == Approx(2.0f).margin(1e-5));
  CHECK(p.z() == Approx(-2.0f).margin(1e-5));
  std::ofstream(dir / "bad.yaml") << "objects:\n  - mesh: tri.obj\n    class: spaceship\nroute: [[0, 0], [1, 0]]\n";
  auto bad = load_scene_file((dir / "bad.yaml").string());
  REQUIRE(!bad.ok());
  CHECK(bad.error().message.find("spaceship") != std::string::npos);
  CHECK(!load_scene_file((dir / "none.yaml").string()).ok());
}

// Found by fuzz_scene_file (2026-12-01): a seafloor extent of 4.4e63 m reached a float-to-int
// conversion out of range (undefined behaviour) and would have sized the heightfield from it.
TEST_CASE("scene files with huge, non-finite or over-fine seafloors are errors naming the key", "[hal]") {
  const auto dir = scene_out_dir();
  auto load_text = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return load_scene_file((dir / name).string());
  };
  const std::string route = "route: [[0, 0], [3, 0], [3, 2]]\n";
  auto huge = load_text("huge.yaml", "name: fuzzseed\nseed: 3\nvehicle_depth_m: 2\nseafloor_depth_m: 6\n"
                        "seafloor: {x_min_m: -4444444444444444444444444444444444444444444444444444444444444444, "
                        "x_max_m: 5, y_min_m: -3, y_max_m: 4, cell_m: 1.0, relief_m: 0.2}\n" + route);
  REQUIRE_FALSE(huge.ok());
  CHECK(huge.error().message.find("seafloor") != std::string::npos);
  CHECK(huge.error().message.find("cell_m") != std::string::npos);
  auto fine = load_text("fine.yaml", "seafloor: {x_min_m: -100, x_max_m: 100, y_min_m: -100, y_max_m: 100, cell_m: 0.001}\n" + route);
  REQUIRE_FALSE(fine.ok());
  CHECK(fine.error().message.find("exceed") != std::string::npos);
  auto nan = load_text("nan.yaml", "seafloor: {x_min_m: .nan, x_max_m: 5, y_min_m: -3, y_max_m: 4}\n" + route);
  REQUIRE_FALSE(nan.ok());
  CHECK(nan.error().message.find("finite") != std::string::npos);
  auto inf_route = load_text("inf_route.yaml", "route: [[0, 0], [.inf, 0]]\n");
  REQUIRE_FALSE(inf_route.ok());
  CHECK(inf_route.error().message.find("route") != std::string::npos);
  // A large site at a coarse cell is still a scene (200 x 200 cells).
  CHECK(load_text("site.yaml", "seafloor: {x_min_m: 0, x_max_m: 1000, y_min_m: 0, y_max_m: 1000, cell_m: 5.0}\n" + route).ok());
}

TEST_CASE("harbor offers the survey route, which select_route picks, and names it does not know are refused", "[hal]") {
  auto harbor = builtin_scene("harbor", 1);
  REQUIRE(harbor.ok());
  const auto own = harbor->route;
  CHECK(harbor->route_name == "default");
  REQUIRE(select_route(*harbor, "").ok());
  REQUIRE(select_route(*harbor, "default").ok());
  CHECK(harbor->route == own);
  REQUIRE(select_route(*harbor, "survey").ok());
  CHECK(harbor->route_name == "survey");
  CHECK(harbor->route != own);
  CHECK(harbor->route.size() >= 10);
  const Status bad = select_route(*harbor, "scenic");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("scenic") != std::string::npos);
  CHECK(bad.error().message.find("default, survey") != std::string::npos);
  auto marina = builtin_scene("marina1", 1);
  REQUIRE(marina.ok());
  CHECK_FALSE(select_route(*marina, "survey").ok());  // harbor's, not every scene's
  // The simulator config's `route` key accepts the names the built-in scenes offer.
  for (const auto& name : builtin_scene_names()) {
    auto scene = builtin_scene(name, 1);
    REQUIRE(scene.ok());
    std::vector<std::string> offered;
    for (const auto& r : scene->routes) offered.push_back(r.name);
    CHECK(offered == builtin_route_names(name));  // named without building the scene
    for (const auto& r : scene->routes) {
      INFO(name << " route " << r.name);
      SimConfig c;
      CHECK(apply_sim_config_yaml("route: " + r.name + "\n", c).ok());
      CHECK(c.route == r.name);
    }
  }
}

}  // namespace orthosonar::sim
