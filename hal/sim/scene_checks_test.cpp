// Issue 40: a scene file that cannot be a mission is an error naming the key: the vehicle
// under the seafloor, a route of zero length, the vehicle starting inside an object.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "hal/sim/scene.hpp"

using namespace orthosonar;

namespace {

std::filesystem::path scene_checks_dir(const std::string& name) {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto d = std::filesystem::path(env ? env : std::filesystem::temp_directory_path().string()) / "scene_checks" / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  // A closed 2 m cube centred on the origin.
  std::ofstream(d / "cube.obj") << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
                                   "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
                                   "f 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  return d;
}

Result<sim::Scene> load_scene_text(const std::filesystem::path& dir, const std::string& yaml) {
  std::ofstream(dir / "s.yaml") << yaml;
  return sim::load_scene_file((dir / "s.yaml").string());
}

const char* kFloor = "seafloor: {x_min_m: -20, x_max_m: 20, y_min_m: -20, y_max_m: 20, cell_m: 2}\n";

}  // namespace

TEST_CASE("scene file: a vehicle below the seafloor is an error naming vehicle_depth_m", "[sim][scene]") {
  const auto d = scene_checks_dir("under_seabed");
  auto ok = load_scene_text(d, std::string("vehicle_depth_m: 3\nseafloor_depth_m: 9\n") + kFloor + "route: [[0, 0], [10, 0]]\n");
  REQUIRE(ok.ok());
  auto bad = load_scene_text(d, std::string("vehicle_depth_m: 12\nseafloor_depth_m: 9\n") + kFloor + "route: [[0, 0], [10, 0]]\n");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("vehicle_depth_m") != std::string::npos);
  CHECK(bad.error().message.find("seafloor_depth_m") != std::string::npos);
}

TEST_CASE("scene file: a route of zero length is an error naming route", "[sim][scene]") {
  const auto d = scene_checks_dir("zero_route");
  auto bad = load_scene_text(d, std::string(kFloor) + "route: [[5, 5], [5, 5], [5, 5]]\n");
  REQUIRE_FALSE(bad.ok());
  INFO(bad.error().message);
  CHECK(bad.error().message.find("route: the waypoints") != std::string::npos);
  CHECK(bad.error().message.find("length") != std::string::npos);
}

TEST_CASE("scene file: a vehicle starting inside an object is an error naming the object", "[sim][scene]") {
  const auto d = scene_checks_dir("inside");
  // The cube at (0, 0, -3) around the start (0, 0) at 3 m depth.
  auto bad = load_scene_text(d, std::string(kFloor) +
                                    "objects:\n  - {mesh: cube.obj, class: other, pose: [10, 10, -3, 0, 0, 0]}\n"
                                    "  - {mesh: cube.obj, class: other, pose: [0, 0, -3, 0, 0, 0]}\n"
                                    "route: [[0, 0], [10, 0]]\n");
  REQUIRE_FALSE(bad.ok());
  INFO(bad.error().message);
  CHECK(bad.error().message.find("objects[1]: the vehicle starts inside") != std::string::npos);
  CHECK(bad.error().message.find("starts inside") != std::string::npos);
  // Beside it, above it, or a deck-like open surface over the start: fine.
  auto ok = load_scene_text(d, std::string(kFloor) +
                                   "objects:\n  - {mesh: cube.obj, class: other, pose: [0, 3, -3, 0, 0, 0]}\n"
                                   "  - {mesh: cube.obj, class: other, pose: [0, 0, -6.5, 0, 0, 0]}\n"
                                   "route: [[0, 0], [10, 0]]\n");
  REQUIRE(ok.ok());
}
