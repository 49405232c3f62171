// Wavefront OBJ: the one reader (v and f lines; polygons fanned; texture and normal
// indices ignored) and the one writer. OBJ has no counts in a header; the bounds are on
// indices: every face index is parsed as a 64-bit integer and must name a vertex read so
// far (1-based, or negative and relative), so a huge or out-of-range index is an error
// naming the file and line, never an out-of-bounds access.
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "hal/sim/mesh_io.hpp"

namespace orthosonar::sim {

Result<TriangleMesh> read_mesh_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{path + ": cannot open"};
  TriangleMesh m;
  std::string line;
  uint64_t line_no = 0;
  std::vector<int> poly;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = path + " line " + std::to_string(line_no) + ": ";
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z)) return Error{where + "bad vertex"};
      for (const double c : {x, y, z})  // NaN or beyond a float: the renderer's BVH and voxel keys break
        if (!(std::abs(c) <= std::numeric_limits<float>::max()))
          return Error{where + "vertex coordinate " + std::to_string(c) + " is not a finite float"};
      if (m.vertices.size() >= static_cast<size_t>(INT32_MAX)) return Error{where + "more vertices than a mesh can index"};
      m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    } else if (kw == "f") {
      poly.clear();
      std::string tok;
      const auto n = static_cast<int64_t>(m.vertices.size());
      while (ls >> tok) {
        // "a", "a/b", "a//c", "a/b/c": the vertex index is the part before the first '/'.
        int64_t idx = 0;
        const char* end = tok.data() + tok.size();
        auto [p, ec] = std::from_chars(tok.data(), end, idx);
        const bool parsed = ec == std::errc() && p != tok.data() && (p == end || *p == '/');
        const int64_t i = idx > 0 ? idx - 1 : n + idx;
        if (!parsed || idx == 0 || i < 0 || i >= n)
          return Error{where + "face index '" + tok + "' out of range (" + std::to_string(n) + " vertices so far)"};
        poly.push_back(static_cast<int>(i));
      }
      if (poly.size() < 3) return Error{where + "face with fewer than 3 corners"};
      for (size_t k = 2; k < poly.size(); ++k) {
        m.triangles.emplace_back(poly[0], poly[k - 1], poly[k]);
        m.object_id.push_back(1);
        m.semantic.push_back(SemanticClass::kOther);
      }
    }
  }
  if (in.bad()) return Error{path + ": read failed"};
  return m;
}

Status write_mesh_obj(const TriangleMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  if (!out) return Error{path + ": cannot open for writing"};
  char buf[128];
  out << "# orthosonar mesh\n";
  for (const auto& v : mesh.vertices) {
    std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", static_cast<double>(v.x()), static_cast<double>(v.y()),
                  static_cast<double>(v.z()));
    out << buf;
  }
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  out.flush();
  if (!out) return Error{path + ": write failed"};
  return Status::Ok();
}

}  // namespace orthosonar::sim
