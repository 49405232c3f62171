#include "reports/ply_io.hpp"

#include <catch2/catch.hpp>
#include <fstream>

#include "reports/test_dir.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

TEST_CASE("binary PLY points and meshes round-trip exactly", "[report]") {
  const auto dir = testing::test_dir("ply_roundtrip");
  const std::vector<Eigen::Vector3f> pts = {{1.5f, -2.25f, 3.0f}, {0.0f, 0.0f, -8.125f}};
  REQUIRE(write_ply_points((dir / "p.ply").string(), pts).ok());
  auto back = read_ply_points((dir / "p.ply").string());
  REQUIRE(back.ok());
  REQUIRE(*back == pts);

  TriangleMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  m.semantic = {SemanticClass::kSeafloor, SemanticClass::kPiling};
  m.object_id = {0, 7};
  REQUIRE(write_ply_mesh((dir / "m.ply").string(), m).ok());
  auto mb = read_ply((dir / "m.ply").string());
  REQUIRE(mb.ok());
  CHECK(mb->vertices == m.vertices);
  CHECK(mb->triangles == m.triangles);
  CHECK(mb->semantic == m.semantic);
  CHECK(mb->object_id == m.object_id);
}

TEST_CASE("ascii PLY with extra properties and a quad face is read", "[report]") {
  const auto dir = testing::test_dir("ply_ascii");
  std::ofstream(dir / "a.ply") << "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\n"
                                  "property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
                                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                  "0 0 0 255\n1 0 0 0\n1 1 0 9\n0 1 0.5 1\n4 0 1 2 3\n";
  auto m = read_ply((dir / "a.ply").string());
  REQUIRE(m.ok());
  REQUIRE(m->vertices.size() == 4);
  CHECK(m->vertices[3].z() == 0.5f);
  REQUIRE(m->triangles.size() == 2);  // the quad fanned
  CHECK(m->triangles[1] == Eigen::Vector3i(0, 2, 3));
  CHECK(m->semantic[0] == SemanticClass::kNone);
}

TEST_CASE("broken PLY files are errors naming the file", "[report]") {
  const auto dir = testing::test_dir("ply_broken");
  std::ofstream(dir / "trunc.ply", std::ios::binary)
      << "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n12345678";
  auto t = read_ply((dir / "trunc.ply").string());
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().message.find("trunc.ply") != std::string::npos);
  std::ofstream(dir / "be.ply") << "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n";
  CHECK_FALSE(read_ply((dir / "be.ply").string()).ok());
  std::ofstream(dir / "idx.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n3 0 1 2\n";
  CHECK_FALSE(read_ply((dir / "idx.ply").string()).ok());
  CHECK_FALSE(read_ply((dir / "missing.ply").string()).ok());
}
