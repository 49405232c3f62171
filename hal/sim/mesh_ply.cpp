// PLY reading (ascii, binary little and big endian) and writing (binary little endian).
#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

#include "hal/sim/mesh_io.hpp"

namespace orthosonar::sim {
namespace {

enum class Format { kAscii, kBinaryLE, kBinaryBE };

struct Property {
  std::string name;
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // non-empty for lists
};
struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
};

int type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

// Reads values one at a time from the body, whatever the format.
class BodyReader {
 public:
  BodyReader(std::istream& in, Format f) : in_(in), format_(f) {}
  bool read(const std::string& type, double& out) {
    if (format_ == Format::kAscii) return static_cast<bool>(in_ >> out);
    const int n = type_size(type);
    unsigned char b[8];
    if (n == 0 || !in_.read(reinterpret_cast<char*>(b), n)) return false;
    const bool swap = (format_ == Format::kBinaryBE) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(b, b + n);
    if (type == "char" || type == "int8") out = static_cast<int8_t>(b[0]);
    else if (type == "uchar" || type == "uint8") out = b[0];
    else if (type == "short" || type == "int16") out = load<int16_t>(b);
    else if (type == "ushort" || type == "uint16") out = load<uint16_t>(b);
    else if (type == "int" || type == "int32") out = load<int32_t>(b);
    else if (type == "uint" || type == "uint32") out = load<uint32_t>(b);
    else if (type == "float" || type == "float32") out = load<float>(b);
    else out = load<double>(b);
    return true;
  }

 private:
  template <class T>
  static double load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }
  std::istream& in_;
  Format format_;
};

}  // namespace

Result<TriangleMesh> read_mesh_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Error{"cannot open mesh '" + path + "'"};
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) return Error{"'" + path + "': not a PLY file (no 'ply' magic)"};
  Format format = Format::kAscii;
  std::vector<Element> elements;
  int line_no = 1;
  while (true) {
    if (!std::getline(in, line)) return Error{"'" + path + "': header has no end_header"};
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "end_header") break;
    if (kw == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii") format = Format::kAscii;
      else if (f == "binary_little_endian") format = Format::kBinaryLE;
      else if (f == "binary_big_endian") format = Format::kBinaryBE;
      else return Error{"'" + path + "' line " + std::to_string(line_no) + ": unknown format '" + f + "'"};
    } else if (kw == "element") {
      Element e;
      ls >> e.name >> e.count;
      elements.push_back(e);
    } else if (kw == "property") {
      if (elements.empty()) return Error{"'" + path + "': property before element"};
      Property p;
      std::string t;
      ls >> t;
      if (t == "list") {
        ls >> p.count_type >> p.type >> p.name;
      } else {
        p.type = t;
        ls >> p.name;
      }
      if (type_size(p.type) == 0 || (!p.count_type.empty() && type_size(p.count_type) == 0))
        return Error{"'" + path + "' line " + std::to_string(line_no) + ": unknown property type"};
      elements.back().props.push_back(p);
    }
  }
  TriangleMesh mesh;
  BodyReader body(in, format);
  for (const auto& e : elements) {
    for (uint64_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      std::vector<int> poly;
      double object_id = 1, semantic = static_cast<double>(SemanticClass::kOther);
      for (const auto& p : e.props) {
        double v = 0;
        if (!p.count_type.empty()) {
          double n = 0;
          if (!body.read(p.count_type, n)) return Error{"'" + path + "': truncated in element '" + e.name + "' #" + std::to_string(i)};
          for (int k = 0; k < static_cast<int>(n); ++k) {
            if (!body.read(p.type, v)) return Error{"'" + path + "': truncated list in '" + e.name + "' #" + std::to_string(i)};
            if (p.name == "vertex_indices" || p.name == "vertex_index") poly.push_back(static_cast<int>(v));
          }
          continue;
        }
        if (!body.read(p.type, v)) return Error{"'" + path + "': truncated in element '" + e.name + "' #" + std::to_string(i)};
        if (e.name == "vertex") {
          if (p.name == "x") xyz[0] = v;
          if (p.name == "y") xyz[1] = v;
          if (p.name == "z") xyz[2] = v;
        } else if (e.name == "face") {
          if (p.name == "object_id") object_id = v;
          if (p.name == "semantic") semantic = v;
        }
      }
      if (e.name == "vertex") {
        mesh.vertices.emplace_back(static_cast<float>(xyz[0]), static_cast<float>(xyz[1]), static_cast<float>(xyz[2]));
      } else if (e.name == "face") {
        if (semantic < 0 || semantic >= kSemanticClassCount) semantic = static_cast<double>(SemanticClass::kOther);
        for (size_t k = 2; k < poly.size(); ++k) {
          mesh.triangles.emplace_back(poly[0], poly[k - 1], poly[k]);
          mesh.object_id.push_back(static_cast<uint32_t>(object_id));
          mesh.semantic.push_back(static_cast<SemanticClass>(static_cast<int>(semantic)));
        }
      }
    }
  }
  if (!mesh.valid()) return Error{"'" + path + "': face index out of range"};
  return mesh;
}

Status write_mesh_ply(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{"cannot write mesh '" + path + "'"};
  out << "ply\nformat binary_little_endian 1.0\ncomment orthosonar scene mesh\n"
      << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nproperty uint object_id\nproperty uchar semantic\nend_header\n";
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian host");
  std::vector<char> buf;
  buf.reserve(mesh.vertices.size() * 12 + mesh.triangles.size() * 18);
  auto put = [&buf](const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    buf.insert(buf.end(), c, c + n);
  };
  for (const auto& v : mesh.vertices) put(v.data(), 12);
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const uint8_t three = 3;
    put(&three, 1);
    put(mesh.triangles[i].data(), 12);
    const uint32_t id = i < mesh.object_id.size() ? mesh.object_id[i] : 0;
    const uint8_t sem = i < mesh.semantic.size() ? static_cast<uint8_t>(mesh.semantic[i]) : 0;
    put(&id, 4);
    put(&sem, 1);
  }
  out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  if (!out) return Error{"write failed for mesh '" + path + "'"};
  return Status::Ok();
}

}  // namespace orthosonar::sim
