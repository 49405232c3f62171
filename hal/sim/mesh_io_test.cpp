#include <catch2/catch.hpp>
#include <cstring>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/primitives.hpp"

namespace orthosonar::sim {
namespace {

std::string mesh_io_out_dir() {
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
  const std::string path = mesh_io_out_dir() + "/sample.ply";
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
  const std::string dir = mesh_io_out_dir();
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
  const std::string path = mesh_io_out_dir() + "/quad.ply";
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
  const std::string path = mesh_io_out_dir() + "/broken.ply";
  std::ofstream(path) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n";
  auto r = read_mesh(path);
  REQUIRE(!r.ok());
  CHECK(r.error().message.find("broken.ply") != std::string::npos);
  CHECK(!read_mesh(mesh_io_out_dir() + "/missing.obj").ok());
  CHECK(!read_mesh(mesh_io_out_dir() + "/x.dae").ok());
}


namespace {

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool mentions(const Error& e, const std::string& a, const std::string& b = "") {
  return e.message.find(a) != std::string::npos && e.message.find(b) != std::string::npos;
}

}  // namespace

TEST_CASE("PLY points round trip exactly, empty too, and keep the map.ply bytes", "[hal]") {
  const std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-0.5f, 0.25f, 7}, {1e-7f, -3e5f, 0}};
  const std::string path = mesh_io_out_dir() + "/points.ply";
  REQUIRE(write_ply_points(pts, path).ok());
  CHECK(read_bytes(path).starts_with("ply\nformat binary_little_endian 1.0\ncomment orthosonar map\nelement vertex 3\n"
                                     "property float x\nproperty float y\nproperty float z\nend_header\n"));
  auto back = read_ply_points(path);
  REQUIRE(back.ok());
  CHECK(*back == pts);
  // A mesh file read as points: its vertices.
  const TriangleMesh m = sample();
  REQUIRE(write_mesh_ply(m, mesh_io_out_dir() + "/mesh_as_points.ply").ok());
  auto verts = read_ply_points(mesh_io_out_dir() + "/mesh_as_points.ply");
  REQUIRE(verts.ok());
  CHECK(*verts == m.vertices);
  REQUIRE(write_ply_points({}, mesh_io_out_dir() + "/empty.ply").ok());
  auto empty = read_ply_points(mesh_io_out_dir() + "/empty.ply");
  REQUIRE(empty.ok());
  CHECK(empty->empty());
}

TEST_CASE("PLY points carry named float properties after x y z, bad names and counts are errors", "[hal]") {
  const std::vector<Eigen::Vector3f> pts = {{1, 2, 3}, {-0.5f, 0.25f, 7}};
  const std::string path = mesh_io_out_dir() + "/points_scalars.ply";
  REQUIRE(write_ply_points(pts, {{"distance_m", {0.5f, 2.0f}}, {"range_m", {10.0f, 20.5f}}}, "a cloud", path).ok());
  const std::string bytes = read_bytes(path);
  const std::string header = "ply\nformat binary_little_endian 1.0\ncomment a cloud\nelement vertex 2\n"
                             "property float x\nproperty float y\nproperty float z\nproperty float distance_m\n"
                             "property float range_m\nend_header\n";
  REQUIRE(bytes.starts_with(header));
  REQUIRE(bytes.size() == header.size() + 2 * 5 * 4);
  float second_range = 0;
  std::memcpy(&second_range, bytes.data() + header.size() + 5 * 4 + 4 * 4, 4);
  CHECK(second_range == 20.5f);
  auto back = read_ply_points(path);  // the reader skips the extra properties
  REQUIRE(back.ok());
  CHECK(*back == pts);
  auto short_values = write_ply_points(pts, {{"distance_m", {0.5f}}}, "c", mesh_io_out_dir() + "/bad1.ply");
  REQUIRE_FALSE(short_values.ok());
  CHECK(mentions(short_values.error(), "bad1.ply", "'distance_m' has 1 values for 2 points"));
  auto bad_name = write_ply_points(pts, {{"dist ance", {0.5f, 1.0f}}}, "c", mesh_io_out_dir() + "/bad2.ply");
  REQUIRE_FALSE(bad_name.ok());
  CHECK(mentions(bad_name.error(), "bad2.ply", "bad vertex property name 'dist ance'"));
  auto clash = write_ply_points(pts, {{"x", {0.5f, 1.0f}}}, "c", mesh_io_out_dir() + "/bad3.ply");
  CHECK_FALSE(clash.ok());
  auto two_lines = write_ply_points(pts, {}, "a\nb", mesh_io_out_dir() + "/bad4.ply");
  CHECK_FALSE(two_lines.ok());
}

TEST_CASE("PLY bytes in memory are the file's bytes and decode the same way", "[hal]") {
  const TriangleMesh m = sample();
  const std::string path = mesh_io_out_dir() + "/memory.ply";
  REQUIRE(write_mesh_ply(m, path).ok());
  const std::string bytes = encode_mesh_ply(m);
  CHECK(bytes == read_bytes(path));
  auto back = decode_mesh_ply(bytes, "attachment scene.ply");
  REQUIRE(back.ok());
  CHECK(back->vertices == m.vertices);
  CHECK(back->triangles == m.triangles);
  CHECK(back->object_id == m.object_id);
  CHECK(back->semantic == m.semantic);
  auto cut = decode_mesh_ply(std::string_view(bytes).substr(0, bytes.size() - 1), "attachment scene.ply");
  REQUIRE_FALSE(cut.ok());
  CHECK(mentions(cut.error(), "attachment scene.ply: element face #", "truncated"));
}

TEST_CASE("PLY in big-endian binary, with doubles, CRLF and a class property loads", "[hal]") {
  std::string be = "ply\r\nformat binary_big_endian 1.0\r\ncomment hand made\r\nelement vertex 3\r\nproperty double x\r\n"
                   "property double y\r\nproperty double z\r\nelement face 1\r\nproperty list uchar uint vertex_indices\r\n"
                   "property uchar class\r\nend_header\r\n";
  auto put_be = [&be](const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    for (size_t i = n; i-- > 0;) be.push_back(c[i]);
  };
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 2.0, -1.0}) put_be(&v, 8);
  be.push_back(3);
  for (uint32_t i : {0u, 1u, 2u}) put_be(&i, 4);
  be.push_back(static_cast<char>(SemanticClass::kPiling));
  write_bytes(mesh_io_out_dir() + "/be.ply", be);
  auto r = read_mesh(mesh_io_out_dir() + "/be.ply");
  REQUIRE(r.ok());
  CHECK(r->vertices[2] == Eigen::Vector3f(0.5f, 2.0f, -1.0f));
  CHECK(r->triangles.size() == 1u);
  CHECK(r->semantic[0] == SemanticClass::kPiling);
}

TEST_CASE("a PLY header claiming 2^64 elements is a clear error, not a hang or an allocation", "[hal]") {
  const std::string dir = mesh_io_out_dir();
  for (const char* format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
    INFO(format);
    write_bytes(dir + "/huge.ply", std::string("ply\nformat ") + format +
                                       " 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\n"
                                       "property float z\nend_header\n0 0 0 1 1 1 2 2 2\n");
    auto r = read_mesh(dir + "/huge.ply");
    REQUIRE_FALSE(r.ok());
    CHECK(mentions(r.error(), "huge.ply: header: element vertex count 18446744073709551615 exceeds what 18 bytes"));
    CHECK_FALSE(read_ply_points(dir + "/huge.ply").ok());
  }
  // 2^64 itself does not parse; neither does a negative count.
  for (const char* count : {"18446744073709551616", "-1", "12abc"}) {
    write_bytes(dir + "/over.ply", std::string("ply\nformat ascii 1.0\nelement vertex ") + count +
                                       "\nproperty float x\nproperty float y\nproperty float z\nend_header\n");
    auto r = read_mesh(dir + "/over.ply");
    REQUIRE_FALSE(r.ok());
    CHECK(mentions(r.error(), "over.ply: header line 3: element vertex count", "not an unsigned 64-bit integer"));
  }
  // A later element whose count overflows what is left after the earlier ones.
  write_bytes(dir + "/faces.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                                  "property float y\nproperty float z\nelement face 4294967296\n"
                                  "property list uchar int vertex_indices\nend_header\n" + std::string(12 + 64, '\0'));
  auto f = read_mesh(dir + "/faces.ply");
  REQUIRE_FALSE(f.ok());
  CHECK(mentions(f.error(), "element face count 4294967296 exceeds what 76 bytes"));
  // An element with no properties would take no bytes: its count is not believed.
  write_bytes(dir + "/empty_element.ply", "ply\nformat ascii 1.0\nelement nothing 18446744073709551615\nend_header\n");
  auto e = read_mesh(dir + "/empty_element.ply");
  REQUIRE_FALSE(e.ok());
  CHECK(mentions(e.error(), "element nothing count 18446744073709551615 has no properties"));
  // A list length in the body that the rest of the file cannot hold.
  std::string list = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
  list += std::string(36, '\0') + std::string(4, '\xff') + std::string(12, '\0');
  write_bytes(dir + "/list.ply", list);
  auto l = read_mesh(dir + "/list.ply");
  REQUIRE_FALSE(l.ok());
  CHECK(mentions(l.error(), "list.ply: element face #0", "list vertex_indices length 4294967295 exceeds what 12 bytes"));
}

TEST_CASE("PLY headers without end_header, with junk or an unknown format are errors", "[hal]") {
  const std::string dir = mesh_io_out_dir();
  write_bytes(dir + "/junk.ply", "ply\n" + std::string(3u << 20, 'a'));  // 3 MiB with no newline
  auto j = read_mesh(dir + "/junk.ply");
  REQUIRE_FALSE(j.ok());
  CHECK(mentions(j.error(), "junk.ply: header: no end_header in the first"));
  write_bytes(dir + "/noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\n");
  CHECK(mentions(read_mesh(dir + "/noend.ply").error(), "noend.ply: header: truncated"));
  write_bytes(dir + "/fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n");
  CHECK(mentions(read_mesh(dir + "/fmt.ply").error(), "fmt.ply: header line 2: unknown format"));
  write_bytes(dir + "/magic.ply", "plx\nformat ascii 1.0\nend_header\n");
  CHECK(mentions(read_mesh(dir + "/magic.ply").error(), "magic.ply: not a PLY file"));
  write_bytes(dir + "/idx.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                "0 0 0\n3 0 1 2\n");
  CHECK(mentions(read_mesh(dir + "/idx.ply").error(), "idx.ply: element face #0", "vertex index 1 out of range (1 vertices)"));
}

TEST_CASE("every truncation of a PLY or STL file is an error naming the file", "[hal]") {
  TriangleMesh m;
  MeshBuilder(m).box({0, 0, 0}, {1, 2, 3}, 0, {7, SemanticClass::kDock});  // 12 triangles
  const std::string dir = mesh_io_out_dir();
  REQUIRE(write_mesh_ply(m, dir + "/full.ply").ok());
  REQUIRE(write_mesh_stl(m, dir + "/full.stl", true).ok());
  REQUIRE(write_mesh_stl(m, dir + "/full_ascii.stl", false).ok());
  for (const char* name : {"full.ply", "full.stl", "full_ascii.stl"}) {
    const std::string bytes = read_bytes(dir + "/" + name);
    const std::string ext = std::string(name).substr(std::string(name).rfind('.'));
    const std::string cut = dir + "/cut" + ext;
    size_t failures = 0, cases = 0;
    // Every prefix for the binary files; ascii STL ends inside a facet or is complete.
    for (size_t n = 0; n < bytes.size(); n += (ext == ".stl" && bytes[0] == 's') ? 7 : 1) {
      write_bytes(cut, bytes.substr(0, n));
      auto r = read_mesh(cut);
      ++cases;
      if (!r.ok()) {
        ++failures;
        CHECK(r.error().message.find("cut" + ext) != std::string::npos);
      } else {
        CHECK(r->valid());  // an ascii prefix that ends between facets is a smaller (or, cut in the trailer, the same) mesh
        CHECK(r->triangles.size() <= m.triangles.size());
      }
    }
    INFO(name << ": " << failures << " of " << cases << " prefixes rejected");
    if (bytes[0] != 's') CHECK(failures == cases);
  }
}

TEST_CASE("a binary STL claiming more triangles than its bytes is a clear error", "[hal]") {
  const std::string dir = mesh_io_out_dir();
  std::string stl(80, ' ');
  const uint32_t n = 0xffffffffu;
  stl.append(reinterpret_cast<const char*>(&n), 4);
  stl.append(100, '\0');
  write_bytes(dir + "/huge.stl", stl);
  auto r = read_mesh(dir + "/huge.stl");
  REQUIRE_FALSE(r.ok());
  CHECK(mentions(r.error(), "huge.stl: header: triangle count 4294967295 exceeds what 100 bytes of data can hold"));
  // A binary STL whose 80-byte header starts with "solid" is still binary.
  TriangleMesh m;
  MeshBuilder(m).box({0, 0, 0}, {1, 1, 1}, 0, {1, SemanticClass::kOther});
  REQUIRE(write_mesh_stl(m, dir + "/solid_bin.stl", true).ok());
  std::string bytes = read_bytes(dir + "/solid_bin.stl");
  bytes.replace(0, 10, "solid cube");
  write_bytes(dir + "/solid_bin.stl", bytes);
  auto b = read_mesh(dir + "/solid_bin.stl");
  REQUIRE(b.ok());
  CHECK(corners(*b) == corners(m));
  write_bytes(dir + "/short.stl", "tiny");
  CHECK(mentions(read_mesh(dir + "/short.stl").error(), "short.stl: header: 4 bytes"));
}

TEST_CASE("OBJ face indices out of range, 2^64 or 0 are errors naming the line", "[hal]") {
  const std::string dir = mesh_io_out_dir();
  const std::string verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  for (const char* face : {"f 1 2 18446744073709551616", "f 1 2 18446744073709551615", "f 1 2 4", "f 0 1 2",
                           "f 1 2 -4", "f 1 2 x", "f 1 2"}) {
    INFO(face);
    write_bytes(dir + "/bad.obj", "# comment\n" + verts + face + "\n");
    auto r = read_mesh(dir + "/bad.obj");
    REQUIRE_FALSE(r.ok());
    CHECK(mentions(r.error(), "bad.obj line 5: "));
  }
  write_bytes(dir + "/rel.obj", verts + "f -3/1/1 -2//2 -1\nf 1/1 2/2 3/3\n");
  auto ok = read_mesh(dir + "/rel.obj");
  REQUIRE(ok.ok());
  CHECK(ok->triangles == std::vector<Eigen::Vector3i>{{0, 1, 2}, {0, 1, 2}});
  write_bytes(dir + "/badv.obj", "v 0 0\n");
  CHECK(mentions(read_mesh(dir + "/badv.obj").error(), "badv.obj line 1: bad vertex"));
}

// One reader and one writer per format (STYLE.md): the format's markers appear in code
// (comments stripped) only in the files that implement it. Tests may write files by hand.
TEST_CASE("each file format has one implementation in the source tree", "[hal]") {
  namespace fs = std::filesystem;
  const char* src = std::getenv("ORTHOSONAR_SOURCE");
  REQUIRE(src != nullptr);
  const std::vector<std::pair<std::string, std::vector<std::string>>> markers = {
      {"end_header", {"hal/sim/ply_header.cpp", "hal/sim/mesh_ply.cpp"}},
      {"element vertex", {"hal/sim/mesh_ply.cpp"}},
      {"endsolid", {"hal/sim/mesh_stl.cpp"}},
      {"facet normal", {"hal/sim/mesh_stl.cpp"}},
      {"kw == \"v\"", {"hal/sim/mesh_obj.cpp"}},
      {"DATA binary", {"replay/outputs/pcd_io.cpp"}},
      {"DATA ascii", {"replay/outputs/pcd_io.cpp"}},
      {"VIEWPOINT", {"replay/outputs/pcd_header.cpp"}},
      {"pcl/io/", {"replay/outputs/pcd_io.cpp"}},
  };
  std::vector<std::string> offenders;
  for (const char* top : {"core", "hal", "replay", "reports", "tools", "golden"}) {
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(src) / top)) {
      const std::string rel = fs::relative(entry.path(), src).generic_string();
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp") || rel.ends_with("_test.cpp")) continue;
      std::ifstream in(entry.path());
      std::string line, code;
      while (std::getline(in, line)) code += line.substr(0, line.find("//")) + "\n";
      for (const auto& [marker, owners] : markers)
        if (code.find(marker) != std::string::npos && std::find(owners.begin(), owners.end(), rel) == owners.end())
          offenders.push_back(rel + " contains \"" + marker + "\"");
    }
  }
  INFO([&] {
    std::string s;
    for (const auto& o : offenders) s += o + "\n";
    return s;
  }());
  CHECK(offenders.empty());
}

}  // namespace orthosonar::sim

namespace orthosonar::sim {

// Issue 35: NaN, infinite or beyond-float vertices loaded as they were and reached the
// renderer's BVH and int64(floor(NaN)) voxel keys; each format now names the file and where.
TEST_CASE("mesh vertices that are not finite floats are errors naming the file and where", "[hal]") {
  const std::string dir = mesh_io_out_dir();
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (const std::string bad : {"nan", "inf", "-inf", "1e39"}) {
    INFO(bad);
    write_bytes(dir + "/nonfinite.ply", ply_head + "0 0 0\n1 " + bad + " 0\n0 1 0\n3 0 1 2\n");
    auto p = read_mesh(dir + "/nonfinite.ply");
    REQUIRE_FALSE(p.ok());
    CHECK(mentions(p.error(), "nonfinite.ply: element vertex #1", "not a finite float"));
  }
  write_bytes(dir + "/nonfinite.obj", "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n");
  auto o = read_mesh(dir + "/nonfinite.obj");
  REQUIRE_FALSE(o.ok());
  CHECK(mentions(o.error(), "nonfinite.obj line 3", "not a finite float"));
  write_bytes(dir + "/nonfinite_ascii.stl",
              "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 -1e39 0\nendloop\nendfacet\n"
              "endsolid x\n");
  auto a = read_mesh(dir + "/nonfinite_ascii.stl");
  REQUIRE_FALSE(a.ok());
  CHECK(mentions(a.error(), "nonfinite_ascii.stl: ascii STL vertex #2", "not a finite float"));
  // Binary STL: a NaN in the second triangle's third corner.
  TriangleMesh m;
  MeshBuilder(m).box({0, 0, 0}, {1, 1, 1}, 0, {1, SemanticClass::kOther});
  REQUIRE(write_mesh_stl(m, dir + "/nonfinite_bin.stl", true).ok());
  std::string bytes = read_bytes(dir + "/nonfinite_bin.stl");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const size_t at = 84 + 50 * 1 + 12 + 12 * 2 + 4;
  bytes.replace(at, 4, reinterpret_cast<const char*>(&nan), 4);
  write_bytes(dir + "/nonfinite_bin.stl", bytes);
  auto b = read_mesh(dir + "/nonfinite_bin.stl");
  REQUIRE_FALSE(b.ok());
  CHECK(mentions(b.error(), "nonfinite_bin.stl: triangle 1 (byte offset 170)", "vertex 2 is not finite"));
}

}  // namespace orthosonar::sim
