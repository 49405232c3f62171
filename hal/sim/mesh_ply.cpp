// PLY: the one reader (ascii, binary little and big endian; meshes and point clouds) and
// the one writer (binary little endian). Headers go through ply::parse_header, which
// bounds every count by the bytes after end_header; list lengths read from the body are
// bounded the same way, so reserve() below never sees an unchecked count.
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <climits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/ply_header.hpp"

namespace orthosonar::sim {
namespace {

using ply::Format;
using ply::Type;

// Values from the body, one at a time, whatever the format.
class Body {
 public:
  Body(std::string_view bytes, Format f) : b_(bytes), format_(f) {}

  bool read(Type t, double& out) {
    if (format_ == Format::kAscii) return read_ascii(out);
    const size_t n = ply::type_size(t);
    if (b_.size() - pos_ < n) return false;
    unsigned char v[8];
    std::memcpy(v, b_.data() + pos_, n);
    pos_ += n;
    if ((format_ == Format::kBinaryBigEndian) == (std::endian::native == std::endian::little)) std::reverse(v, v + n);
    switch (t) {
      case Type::kI8: out = static_cast<int8_t>(v[0]); break;
      case Type::kU8: out = v[0]; break;
      case Type::kI16: out = load<int16_t>(v); break;
      case Type::kU16: out = load<uint16_t>(v); break;
      case Type::kI32: out = load<int32_t>(v); break;
      case Type::kU32: out = load<uint32_t>(v); break;
      case Type::kF32: out = load<float>(v); break;
      case Type::kF64: out = load<double>(v); break;
    }
    return true;
  }

  // Bytes not yet consumed (an upper bound on what is left to read).
  uint64_t remaining() const { return b_.size() - pos_; }
  uint64_t offset() const { return pos_; }

 private:
  template <class T>
  static double load(const unsigned char* v) {
    T x;
    std::memcpy(&x, v, sizeof x);
    return static_cast<double>(x);
  }
  bool read_ascii(double& out) {
    while (pos_ < b_.size() && (b_[pos_] == ' ' || b_[pos_] == '\t' || b_[pos_] == '\r' || b_[pos_] == '\n')) ++pos_;
    if (pos_ < b_.size() && b_[pos_] == '+') ++pos_;
    const char* first = b_.data() + pos_;
    const char* last = b_.data() + b_.size();
    auto [p, ec] = std::from_chars(first, last, out);
    if (ec != std::errc() || p == first) return false;
    pos_ = static_cast<size_t>(p - b_.data());
    return true;
  }

  std::string_view b_;
  Format format_;
  size_t pos_ = 0;
};

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

Result<std::string> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{path + ": cannot open"};
  std::error_code ec;
  const uint64_t size = std::filesystem::file_size(path, ec);
  if (ec) return Error{path + ": cannot stat (" + ec.message() + ")"};
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  bytes.resize(static_cast<size_t>(in.gcount()));
  return bytes;
}

// Decodes every element of a PLY file's bytes; keeps vertices, and faces when want_faces.
// `path` names the bytes in errors.
Result<TriangleMesh> decode_ply(std::string_view bytes, const std::string& path, bool want_faces) {
  auto header = ply::parse_header(bytes, bytes.size(), path);
  if (!header) return header.error();
  const ply::Header& h = *header;
  uint64_t vertex_count = 0;
  for (const auto& e : h.elements)
    if (e.name == "vertex") vertex_count = e.count;
  if (vertex_count > static_cast<uint64_t>(INT_MAX))
    return Error{path + ": header: element vertex count " + std::to_string(vertex_count) + " is more than a mesh can index"};

  TriangleMesh mesh;
  Body body(bytes.substr(h.body_offset), h.format);
  auto at = [&](const ply::Element& e, uint64_t i) {
    return path + ": element " + e.name + " #" + std::to_string(i) + " (body byte " + std::to_string(body.offset()) + "): ";
  };
  const bool ascii = h.format == Format::kAscii;
  for (const ply::Element& e : h.elements) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face" && want_faces;
    const int ix = e.scalar_index("x"), iy = e.scalar_index("y"), iz = e.scalar_index("z");
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) return Error{path + ": element vertex lacks x, y or z"};
    if (is_vertex) mesh.vertices.reserve(static_cast<size_t>(e.count));  // bounded by the header check
    std::vector<int> poly;
    for (uint64_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      double object_id = 1, semantic = static_cast<double>(SemanticClass::kOther);
      poly.clear();
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const ply::Property& p = e.properties[k];
        double v = 0;
        if (p.is_list) {
          double n = 0;
          if (!body.read(p.count_type, n)) return Error{at(e, i) + "truncated or malformed list count of " + p.name};
          // Each list item takes at least its binary size, or a digit and a separator.
          const uint64_t item = ascii ? 2 : ply::type_size(p.type);
          const uint64_t room = (body.remaining() + (ascii ? 1 : 0)) / item;
          if (!(n >= 0 && n <= static_cast<double>(room)) || n != static_cast<double>(static_cast<uint64_t>(n)))
            return Error{at(e, i) + "list " + p.name + " length " + number(n) + " exceeds what " +
                         std::to_string(body.remaining()) + " bytes of data can hold"};
          const bool corners = is_face && (p.name == "vertex_indices" || p.name == "vertex_index");
          for (uint64_t c = 0; c < static_cast<uint64_t>(n); ++c) {
            if (!body.read(p.type, v)) return Error{at(e, i) + "truncated or malformed list " + p.name};
            if (!corners) continue;
            if (!(v >= 0 && v < static_cast<double>(vertex_count)) || v != static_cast<double>(static_cast<int64_t>(v)))
              return Error{at(e, i) + "vertex index " + number(v) + " out of range (" +
                           std::to_string(vertex_count) + " vertices)"};
            poly.push_back(static_cast<int>(v));  // 0 <= v < vertex_count <= INT_MAX
          }
          continue;
        }
        if (!body.read(p.type, v)) return Error{at(e, i) + "truncated or malformed property " + p.name};
        const int ki = static_cast<int>(k);
        if (is_vertex) {
          if (ki == ix) xyz[0] = v;
          if (ki == iy) xyz[1] = v;
          if (ki == iz) xyz[2] = v;
        } else if (is_face) {
          if (p.name == "object_id") object_id = v;
          if (p.name == "semantic" || p.name == "class") semantic = v;
        }
      }
      if (is_vertex) {
        for (const double c : xyz)  // NaN or beyond a float: the renderer's BVH and voxel keys break
          if (!(std::abs(c) <= std::numeric_limits<float>::max()))
            return Error{at(e, i) + "x, y or z " + std::to_string(c) + " is not a finite float"};
        mesh.vertices.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2]));
      } else if (is_face) {
        if (!(semantic >= 0 && semantic < kSemanticClassCount)) semantic = static_cast<double>(SemanticClass::kOther);
        if (!(object_id >= 0 && object_id <= static_cast<double>(UINT32_MAX))) object_id = 0;
        for (size_t c = 2; c < poly.size(); ++c) {
          mesh.triangles.emplace_back(poly[0], poly[c - 1], poly[c]);
          mesh.object_id.push_back(static_cast<uint32_t>(object_id));
          mesh.semantic.push_back(static_cast<SemanticClass>(static_cast<int>(semantic)));
        }
      }
    }
  }
  if (!mesh.valid()) return Error{path + ": face index out of range"};
  return mesh;
}

Status write_file(const std::string& path, const std::string& header, const std::vector<char>& body) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return Error{path + ": cannot open for writing"};
  out << header;
  out.write(body.data(), static_cast<std::streamsize>(body.size()));
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Status::Ok();
}

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");

void put(std::vector<char>& buf, const void* p, size_t n) {
  const char* c = static_cast<const char*>(p);
  buf.insert(buf.end(), c, c + n);
}

}  // namespace

Result<TriangleMesh> read_mesh_ply(const std::string& path) {
  auto bytes = slurp(path);
  if (!bytes) return bytes.error();
  return decode_ply(*bytes, path, true);
}

Result<TriangleMesh> decode_mesh_ply(std::string_view bytes, const std::string& name) {
  return decode_ply(bytes, name, true);
}

Result<std::vector<Eigen::Vector3f>> read_ply_points(const std::string& path) {
  auto bytes = slurp(path);
  if (!bytes) return bytes.error();
  auto mesh = decode_ply(*bytes, path, false);
  if (!mesh) return mesh.error();
  return std::move(mesh->vertices);
}

std::string encode_mesh_ply(const TriangleMesh& mesh) {
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment orthosonar scene mesh\nelement vertex " +
                             std::to_string(mesh.vertices.size()) +
                             "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                             std::to_string(mesh.triangles.size()) +
                             "\nproperty list uchar int vertex_indices\nproperty uint object_id\n"
                             "property uchar semantic\nend_header\n";
  std::vector<char> buf;
  buf.reserve(mesh.vertices.size() * 12 + mesh.triangles.size() * 18);
  for (const auto& v : mesh.vertices) put(buf, v.data(), 12);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const uint8_t three = 3;
    put(buf, &three, 1);
    put(buf, mesh.triangles[i].data(), 12);
    const uint32_t id = i < mesh.object_id.size() ? mesh.object_id[i] : 0;
    const uint8_t sem = i < mesh.semantic.size() ? static_cast<uint8_t>(mesh.semantic[i]) : 0;
    put(buf, &id, 4);
    put(buf, &sem, 1);
  }
  header.append(buf.data(), buf.size());
  return header;
}

Status write_mesh_ply(const TriangleMesh& mesh, const std::string& path) {
  return write_file(path, encode_mesh_ply(mesh), {});
}

Status write_ply_points(const std::vector<Eigen::Vector3f>& points, const std::string& path) {
  return write_ply_points(points, {}, "orthosonar map", path);
}

Status write_ply_points(const std::vector<Eigen::Vector3f>& points, const std::vector<PlyScalar>& scalars,
                        const std::string& comment, const std::string& path) {
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment " + comment + "\nelement vertex " +
                       std::to_string(points.size()) + "\nproperty float x\nproperty float y\nproperty float z\n";
  for (const PlyScalar& s : scalars) {
    const bool named = !s.name.empty() && std::all_of(s.name.begin(), s.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    });
    if (!named || s.name == "x" || s.name == "y" || s.name == "z")
      return Error{path + ": bad vertex property name '" + s.name + "'"};
    if (s.values.size() != points.size())
      return Error{path + ": property '" + s.name + "' has " + std::to_string(s.values.size()) + " values for " +
                   std::to_string(points.size()) + " points"};
    header += "property float " + s.name + "\n";
  }
  if (comment.find('\n') != std::string::npos) return Error{path + ": a header comment cannot hold a line break"};
  header += "end_header\n";
  std::vector<char> buf;
  buf.reserve(points.size() * (12 + 4 * scalars.size()));
  for (size_t i = 0; i < points.size(); ++i) {
    put(buf, points[i].data(), 12);
    for (const PlyScalar& s : scalars) put(buf, &s.values[i], 4);
  }
  return write_file(path, header, buf);
}

}  // namespace orthosonar::sim
