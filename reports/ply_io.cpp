#include "reports/ply_io.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace orthosonar::reports {
namespace {

static_assert(std::endian::native == std::endian::little, "binary PLY I/O assumes a little-endian host");

enum class Type { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

bool parse_type(const std::string& s, Type& t) {
  if (s == "char" || s == "int8") t = Type::kI8;
  else if (s == "uchar" || s == "uint8") t = Type::kU8;
  else if (s == "short" || s == "int16") t = Type::kI16;
  else if (s == "ushort" || s == "uint16") t = Type::kU16;
  else if (s == "int" || s == "int32") t = Type::kI32;
  else if (s == "uint" || s == "uint32") t = Type::kU32;
  else if (s == "float" || s == "float32") t = Type::kF32;
  else if (s == "double" || s == "float64") t = Type::kF64;
  else return false;
  return true;
}

size_t type_size(Type t) {
  switch (t) {
    case Type::kI8: case Type::kU8: return 1;
    case Type::kI16: case Type::kU16: return 2;
    case Type::kI32: case Type::kU32: case Type::kF32: return 4;
    case Type::kF64: return 8;
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::kF32;
  bool is_list = false;
  Type count_type = Type::kU8;
};

struct Element {
  std::string name;
  size_t count = 0;
  std::vector<Property> properties;
};

template <class T>
double load_as(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return static_cast<double>(v);
}

double decode(Type t, const char* p) {
  switch (t) {
    case Type::kI8: return load_as<int8_t>(p);
    case Type::kU8: return load_as<uint8_t>(p);
    case Type::kI16: return load_as<int16_t>(p);
    case Type::kU16: return load_as<uint16_t>(p);
    case Type::kI32: return load_as<int32_t>(p);
    case Type::kU32: return load_as<uint32_t>(p);
    case Type::kF32: return load_as<float>(p);
    case Type::kF64: return load_as<double>(p);
  }
  return 0.0;
}

// Reads one value of type t from the body (ascii token or binary bytes).
class BodyReader {
 public:
  BodyReader(std::istream& in, bool ascii) : in_(in), ascii_(ascii) {}
  bool read(Type t, double& out) {
    if (ascii_) return static_cast<bool>(in_ >> out);
    char buf[8];
    if (!in_.read(buf, static_cast<std::streamsize>(type_size(t)))) return false;
    out = decode(t, buf);
    return true;
  }

 private:
  std::istream& in_;
  bool ascii_;
};

Error fail(const std::string& path, const std::string& what) { return Error{"PLY '" + path + "': " + what}; }

}  // namespace

Result<TriangleMesh> read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail(path, "cannot open");
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return fail(path, "missing 'ply' magic");
  bool ascii = false;
  bool have_format = false;
  std::vector<Element> elements;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "end_header") break;
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      std::string fmt;
      ls >> fmt;
      if (fmt == "ascii") ascii = true;
      else if (fmt != "binary_little_endian") return fail(path, "unsupported format '" + fmt + "'");
      have_format = true;
    } else if (word == "element") {
      Element e;
      ls >> e.name >> e.count;
      if (!ls) return fail(path, "bad element line '" + line + "'");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) return fail(path, "property before any element");
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        std::string ct, it;
        ls >> ct >> it >> p.name;
        p.is_list = true;
        if (!parse_type(ct, p.count_type) || !parse_type(it, p.type)) return fail(path, "bad list type in '" + line + "'");
      } else {
        ls >> p.name;
        if (!parse_type(t, p.type)) return fail(path, "bad property type in '" + line + "'");
      }
      elements.back().properties.push_back(p);
    } else {
      return fail(path, "unexpected header line '" + line + "'");
    }
  }
  if (!have_format) return fail(path, "no format line");

  TriangleMesh mesh;
  BodyReader body(in, ascii);
  for (const Element& e : elements) {
    const bool is_vertex = e.name == "vertex";
    const bool is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1;
    for (size_t k = 0; k < e.properties.size(); ++k) {
      if (e.properties[k].name == "x") ix = static_cast<int>(k);
      if (e.properties[k].name == "y") iy = static_cast<int>(k);
      if (e.properties[k].name == "z") iz = static_cast<int>(k);
    }
    if (is_vertex && (ix < 0 || iy < 0 || iz < 0)) return fail(path, "vertex element lacks x, y or z");
    for (size_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      std::vector<int> corners;
      double semantic = 0.0, object_id = 0.0;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (p.is_list) {
          double n = 0.0;
          if (!body.read(p.count_type, n) || n < 0 || n > 1e6) return fail(path, "truncated list in '" + e.name + "'");
          for (int c = 0; c < static_cast<int>(n); ++c) {
            double v = 0.0;
            if (!body.read(p.type, v)) return fail(path, "truncated list in '" + e.name + "'");
            if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) corners.push_back(static_cast<int>(v));
          }
          continue;
        }
        double v = 0.0;
        if (!body.read(p.type, v)) return fail(path, "truncated body in element '" + e.name + "' at item " + std::to_string(i));
        const int ki = static_cast<int>(k);
        if (is_vertex && ki == ix) xyz[0] = v;
        if (is_vertex && ki == iy) xyz[1] = v;
        if (is_vertex && ki == iz) xyz[2] = v;
        if (is_face && (p.name == "semantic" || p.name == "class")) semantic = v;
        if (is_face && p.name == "object_id") object_id = v;
      }
      if (is_vertex) {
        mesh.vertices.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2]));
      } else if (is_face) {
        for (size_t c = 2; c < corners.size(); ++c) {
          mesh.triangles.emplace_back(corners[0], corners[c - 1], corners[c]);
          const bool known = semantic >= 0 && semantic < kSemanticClassCount;
          mesh.semantic.push_back(known ? static_cast<SemanticClass>(static_cast<int>(semantic)) : SemanticClass::kOther);
          mesh.object_id.push_back(static_cast<uint32_t>(object_id));
        }
      }
    }
  }
  if (!mesh.valid()) return fail(path, "face index out of range");
  return mesh;
}

Result<std::vector<Eigen::Vector3f>> read_ply_points(const std::string& path) {
  auto mesh = read_ply(path);
  if (!mesh) return mesh.error();
  return std::move(mesh->vertices);
}

namespace {

template <class T>
void put(std::ofstream& out, T v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

Status write_ply_points(const std::string& path, const std::vector<Eigen::Vector3f>& points) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return fail(path, "cannot create");
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << points.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  for (const auto& p : points) {
    put(out, p.x());
    put(out, p.y());
    put(out, p.z());
  }
  if (!out) return fail(path, "write failed");
  return Status::Ok();
}

Status write_ply_mesh(const std::string& path, const TriangleMesh& mesh) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return fail(path, "cannot create");
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nproperty uchar semantic\nproperty uint object_id\nend_header\n";
  for (const auto& v : mesh.vertices) {
    put(out, v.x());
    put(out, v.y());
    put(out, v.z());
  }
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    put(out, uint8_t{3});
    for (int c = 0; c < 3; ++c) put(out, static_cast<int32_t>(mesh.triangles[i][c]));
    put(out, static_cast<uint8_t>(i < mesh.semantic.size() ? mesh.semantic[i] : SemanticClass::kNone));
    put(out, i < mesh.object_id.size() ? mesh.object_id[i] : uint32_t{0});
  }
  if (!out) return fail(path, "write failed");
  return Status::Ok();
}

}  // namespace orthosonar::reports
