// OBJ and STL reading and writing, and the reader dispatch by extension.
#include "hal/sim/mesh_io.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

namespace orthosonar::sim {
namespace {

void add_triangle(TriangleMesh& m, int a, int b, int c) {
  m.triangles.emplace_back(a, b, c);
  m.object_id.push_back(1);
  m.semantic.push_back(SemanticClass::kOther);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

Result<TriangleMesh> read_stl_ascii(const std::string& path) {
  std::ifstream in(path);
  TriangleMesh m;
  std::string word;
  int corner = 0;
  while (in >> word) {
    if (word != "vertex") continue;
    double x, y, z;
    if (!(in >> x >> y >> z)) return Error{"'" + path + "': bad ascii STL vertex"};
    m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    if (++corner == 3) {
      const int n = static_cast<int>(m.vertices.size());
      add_triangle(m, n - 3, n - 2, n - 1);
      corner = 0;
    }
  }
  if (corner != 0) return Error{"'" + path + "': ascii STL ends inside a facet"};
  return m;
}

}  // namespace

Result<TriangleMesh> read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return read_mesh_ply(path);
  if (ext == ".obj") return read_mesh_obj(path);
  if (ext == ".stl") return read_mesh_stl(path);
  return Error{"mesh '" + path + "': unknown extension (expected .ply, .obj or .stl)"};
}

Result<TriangleMesh> read_mesh_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"cannot open mesh '" + path + "'"};
  TriangleMesh m;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z)) return Error{"'" + path + "' line " + std::to_string(line_no) + ": bad vertex"};
      m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    } else if (kw == "f") {
      std::vector<int> poly;
      std::string tok;
      while (ls >> tok) {
        const int idx = std::atoi(tok.c_str());  // "a", "a/b", "a//c", "a/b/c"
        const int n = static_cast<int>(m.vertices.size());
        const int i = idx > 0 ? idx - 1 : n + idx;
        if (idx == 0 || i < 0 || i >= n) return Error{"'" + path + "' line " + std::to_string(line_no) + ": bad face index '" + tok + "'"};
        poly.push_back(i);
      }
      for (size_t k = 2; k < poly.size(); ++k) add_triangle(m, poly[0], poly[k - 1], poly[k]);
    }
  }
  return m;
}

Result<TriangleMesh> read_mesh_stl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{"cannot open mesh '" + path + "'"};
  in.seekg(0, std::ios::end);
  const auto size = static_cast<uint64_t>(in.tellg());
  in.seekg(0);
  char header[84] = {};
  if (size >= 84) in.read(header, 84);
  uint32_t n = 0;
  std::memcpy(&n, header + 80, 4);
  if (size >= 84 && size == 84 + 50ull * n) {
    TriangleMesh m;
    m.vertices.reserve(3ull * n);
    for (uint32_t t = 0; t < n; ++t) {
      char rec[50];
      if (!in.read(rec, 50)) return Error{"'" + path + "': truncated binary STL at triangle " + std::to_string(t)};
      for (int c = 0; c < 3; ++c) {
        float v[3];
        std::memcpy(v, rec + 12 + 12 * c, 12);
        m.vertices.emplace_back(v[0], v[1], v[2]);
      }
      const int k = static_cast<int>(m.vertices.size());
      add_triangle(m, k - 3, k - 2, k - 1);
    }
    return m;
  }
  if (std::strncmp(header, "solid", 5) == 0) return read_stl_ascii(path);
  return Error{"'" + path + "': neither binary STL (size mismatch) nor ascii STL"};
}

Status write_mesh_obj(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  if (!out) return Error{"cannot write mesh '" + path + "'"};
  char buf[128];
  out << "# orthosonar mesh\n";
  for (const auto& v : mesh.vertices) {
    std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", static_cast<double>(v.x()),
                  static_cast<double>(v.y()), static_cast<double>(v.z()));
    out << buf;
  }
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  if (!out) return Error{"write failed for mesh '" + path + "'"};
  return Status::Ok();
}

Status write_mesh_stl(const TriangleMesh& mesh, const std::string& path, bool binary) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{"cannot write mesh '" + path + "'"};
  auto normal = [&](const Eigen::Vector3i& t) {
    const Eigen::Vector3f& a = mesh.vertices[static_cast<size_t>(t[0])];
    Eigen::Vector3f n = (mesh.vertices[static_cast<size_t>(t[1])] - a).cross(mesh.vertices[static_cast<size_t>(t[2])] - a);
    const float len = n.norm();
    return len > 0 ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
  };
  if (binary) {
    static_assert(std::endian::native == std::endian::little, "STL writer assumes a little-endian host");
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
  if (!out) return Error{"write failed for mesh '" + path + "'"};
  return Status::Ok();
}

}  // namespace orthosonar::sim
