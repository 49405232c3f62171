// STL: the one reader (binary and ascii) and the one writer. Bounded: a binary file's
// triangle count (uint32 at byte 80) must fit in the bytes after the 84-byte header
// (50 bytes per triangle) before anything is allocated; an ascii file has no count and is
// read token by token, so its size bounds it.
#include <bit>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "hal/sim/mesh_io.hpp"

namespace orthosonar::sim {
namespace {

static_assert(std::endian::native == std::endian::little, "STL I/O assumes a little-endian host");

void add_triangle(TriangleMesh& m, int a, int b, int c) {
  m.triangles.emplace_back(a, b, c);
  m.object_id.push_back(1);
  m.semantic.push_back(SemanticClass::kOther);
}

// "solid" followed by text: binary files may start with "solid" too, but their count and
// float fields hold control bytes within the first few hundred bytes.
bool looks_ascii(const char* head, size_t n) {
  if (n < 5 || std::strncmp(head, "solid", 5) != 0) return false;
  for (size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(head[i]);
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f' && c != '\v') return false;
  }
  return true;
}

Result<TriangleMesh> read_stl_ascii(std::ifstream& in, const std::string& path) {
  TriangleMesh m;
  std::string word;
  int corner = 0;
  while (in >> word) {
    if (word != "vertex") continue;
    double x, y, z;
    if (!(in >> x >> y >> z)) return Error{path + ": bad ascii STL vertex #" + std::to_string(m.vertices.size())};
    for (const double c : {x, y, z})
      if (!(std::abs(c) <= std::numeric_limits<float>::max()))
        return Error{path + ": ascii STL vertex #" + std::to_string(m.vertices.size()) + " coordinate " +
                     std::to_string(c) + " is not a finite float"};
    if (m.vertices.size() >= static_cast<size_t>(INT32_MAX)) return Error{path + ": more vertices than a mesh can index"};
    m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    if (++corner == 3) {
      const int n = static_cast<int>(m.vertices.size());
      add_triangle(m, n - 3, n - 2, n - 1);
      corner = 0;
    }
  }
  if (corner != 0) return Error{path + ": ascii STL ends inside a facet"};
  return m;
}

}  // namespace

Result<TriangleMesh> read_mesh_stl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path + ": cannot stat (" + ec.message() + ")"};
  char head[512] = {};
  in.read(head, sizeof head);
  const auto got = static_cast<size_t>(in.gcount());
  in.clear();
  in.seekg(0);
  if (looks_ascii(head, got)) return read_stl_ascii(in, path);
  if (size < 84) return Error{path + ": header: " + std::to_string(size) + " bytes, shorter than a binary STL header (84)"};
  uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  const uint64_t data = size - 84;
  if (n > data / 50)
    return Error{path + ": header: triangle count " + std::to_string(n) + " exceeds what " + std::to_string(data) +
                 " bytes of data can hold"};
  if (3ull * n > static_cast<uint64_t>(INT32_MAX)) return Error{path + ": more vertices than a mesh can index"};
  TriangleMesh m;
  m.vertices.reserve(3ull * n);
  m.triangles.reserve(n);
  std::vector<char> body(50ull * n);
  in.seekg(84);
  if (!in.read(body.data(), static_cast<std::streamsize>(body.size()))) return Error{path + ": read failed"};
  for (uint32_t t = 0; t < n; ++t) {
    const char* rec = body.data() + 50ull * t;
    for (int c = 0; c < 3; ++c) {
      float v[3];
      std::memcpy(v, rec + 12 + 12 * c, 12);
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        return Error{path + ": triangle " + std::to_string(t) + " (byte offset " + std::to_string(84 + 50ull * t + 12 + 12ull * static_cast<unsigned>(c)) +
                     "): vertex " + std::to_string(c) + " is not finite"};
      m.vertices.emplace_back(v[0], v[1], v[2]);
    }
    const int k = static_cast<int>(m.vertices.size());
    add_triangle(m, k - 3, k - 2, k - 1);
  }
  return m;
}

Status write_mesh_stl(const TriangleMesh& mesh, const std::string& path, bool binary) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{path + ": cannot open for writing"};
  auto normal = [&](const Eigen::Vector3i& t) {
    const Eigen::Vector3f& a = mesh.vertices[static_cast<size_t>(t[0])];
    Eigen::Vector3f n = (mesh.vertices[static_cast<size_t>(t[1])] - a).cross(mesh.vertices[static_cast<size_t>(t[2])] - a);
    const float len = n.norm();
    return len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
  };
  if (binary) {
    char header[80] = "orthosonar mesh";
    out.write(header, 80);
    const auto n = static_cast<uint32_t>(mesh.triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3f nn = normal(t);
      out.write(reinterpret_cast<const char*>(nn.data()), 12);
      for (int c = 0; c < 3; ++c) out.write(reinterpret_cast<const char*>(mesh.vertices[static_cast<size_t>(t[c])].data()), 12);
      const uint16_t attr = 0;
      out.write(reinterpret_cast<const char*>(&attr), 2);
    }
  } else {
    char buf[160];
    out << "solid orthosonar\n";
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3f nn = normal(t);
      std::snprintf(buf, sizeof buf, "facet normal %.9g %.9g %.9g\nouter loop\n", static_cast<double>(nn.x()),
                    static_cast<double>(nn.y()), static_cast<double>(nn.z()));
      out << buf;
      for (int c = 0; c < 3; ++c) {
        const auto& v = mesh.vertices[static_cast<size_t>(t[c])];
        std::snprintf(buf, sizeof buf, "vertex %.9g %.9g %.9g\n", static_cast<double>(v.x()),
                      static_cast<double>(v.y()), static_cast<double>(v.z()));
        out << buf;
      }
      out << "endloop\nendfacet\n";
    }
    out << "endsolid orthosonar\n";
  }
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Status::Ok();
}

}  // namespace orthosonar::sim
