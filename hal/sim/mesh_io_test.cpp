#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/primitives.hpp"

namespace orthosonar::sim {
namespace {

std::string out_dir() {
  const char* env = std::getenv("ORTHOSONAR_TEST_OUT");
  const auto dir = std::filesystem::path(env ? env : std::filesystem::temp_directory_path().string()) / "sim_mesh_io";
  std::filesystem::create_directories(dir);
  return dir.string();
}

TriangleMesh sample() {
  TriangleMesh m;
  MeshBuilder b(m);
  b.box({1, 2, -3}, {1.5, 0.5, 2.25}, 0.3, {4, SemanticClass::kDock});
  b.cylinder({0, 0, -8}, {0, 0, 1}, 0.2, 12, {9, SemanticClass::kPiling});
  return m;
}

// Triangle corners as coordinates, independent of vertex sharing.
std::vector<float> corners(const TriangleMesh& m) {
  std::vector<float> out;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) out.push_back(m.vertices[static_cast<size_t>(t[k])][d]);
  return out;
}

}  // namespace

TEST_CASE("PLY round trip keeps geometry and labels exactly", "[hal]") {
  const TriangleMesh m = sample();
  const std::string path = out_dir() + "/sample.ply";
  REQUIRE(write_mesh_ply(m, path).ok());
  auto r = read_mesh(path);
  REQUIRE(r.ok());
  CHECK(r->vertices == m.vertices);
  CHECK(r->triangles == m.triangles);
  CHECK(r->object_id == m.object_id);
  CHECK(r->semantic == m.semantic);
}

TEST_CASE("OBJ and STL round trips keep the triangles", "[hal]") {
  const TriangleMesh m = sample();
  const std::string dir = out_dir();
  REQUIRE(write_mesh_obj(m, dir + "/sample.obj").ok());
  REQUIRE(write_mesh_stl(m, dir + "/sample_bin.stl", true).ok());
  REQUIRE(write_mesh_stl(m, dir + "/sample_ascii.stl", false).ok());
  for (const char* f : {"/sample.obj", "/sample_bin.stl", "/sample_ascii.stl"}) {
    auto r = read_mesh(dir + f);
    INFO(f);
    REQUIRE(r.ok());
    CHECK(r->valid());
    CHECK(corners(*r) == corners(m));
  }
}

TEST_CASE("ascii PLY with quads and extra properties loads", "[hal]") {
  const std::string path = out_dir() + "/quad.ply";
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                         "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
                         "end_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0 4\n4 0 1 2 3\n";
  auto r = read_mesh(path);
  REQUIRE(r.ok());
  CHECK(r->vertices.size() == 4u);
  CHECK(r->triangles.size() == 2u);
  CHECK(r->vertices[2] == Eigen::Vector3f(1, 1, 0));
}

TEST_CASE("broken mesh files are errors that name the file", "[hal]") {
  const std::string path = out_dir() + "/broken.ply";
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n";
  auto r = read_mesh(path);
  REQUIRE(!r.ok());
  CHECK(r.error().message.find("broken.ply") != std::string::npos);
  CHECK(!read_mesh(out_dir() + "/missing.obj").ok());
  CHECK(!read_mesh(out_dir() + "/x.dae").ok());
}

}  // namespace orthosonar::sim
