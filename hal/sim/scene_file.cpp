// User scenes from YAML (docs/SCENES.md): mesh files placed by poses, classes, an optional
// generated seafloor, and a route inline or in a CSV file.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <sstream>

#include "hal/sim/mesh_io.hpp"
#include "hal/sim/primitives.hpp"
#include "hal/sim/scene.hpp"

namespace orthosonar::sim {
namespace {

namespace fs = std::filesystem;

Result<SemanticClass> parse_class(const std::string& name) {
  for (int c = 0; c < kSemanticClassCount; ++c) {
    if (name == semantic_class_name(static_cast<SemanticClass>(c))) return static_cast<SemanticClass>(c);
  }
  return Error{"unknown class '" + name + "'"};
}

Result<std::vector<Waypoint>> read_route_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Error{"cannot open route file '" + path + "'"};
  std::vector<Waypoint> route;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (const auto h = line.find('#'); h != std::string::npos) line.resize(h);
    for (char& c : line) if (c == ',' || c == ';' || c == '\t') c = ' ';
    std::istringstream ls(line);
    Waypoint w;
    if (!(ls >> w.x_m)) continue;  // blank or comment line
    if (!(ls >> w.y_m)) return Error{"route file '" + path + "' line " + std::to_string(line_no) + ": expected 'x, y'"};
    route.push_back(w);
  }
  return route;
}

// Where a scene YAML's mesh and route files come from: files beside the YAML, or the
// files embedded in a fixture.
struct SceneInputs {
  std::string default_name;
  std::function<Result<TriangleMesh>(const std::string&)> mesh;
  std::function<Result<std::vector<Waypoint>>(const std::string&)> route_file;
};

// A seafloor heightfield of at most this many cells (2000 x 2000): the scene mesh is held in
// memory and ray-traced; an extent from a typo must be an error, not an allocation.
constexpr double kMaxSeafloorCells = 4.0e6;

// Ray-triangle crossings (Moller-Trumbore) of the ray p + t d, t > 0.
int scene_file_crossings(const TriangleMesh& mesh, const Eigen::Vector3d& p, const Eigen::Vector3d& d) {
  int n = 0;
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[static_cast<size_t>(t[0])].cast<double>();
    const Eigen::Vector3d e1 = mesh.vertices[static_cast<size_t>(t[1])].cast<double>() - a;
    const Eigen::Vector3d e2 = mesh.vertices[static_cast<size_t>(t[2])].cast<double>() - a;
    const Eigen::Vector3d h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-12) continue;
    const Eigen::Vector3d sv = p - a;
    const double u = sv.dot(h) / det;
    if (u < 0.0 || u > 1.0) continue;
    const Eigen::Vector3d q = sv.cross(e1);
    const double v = d.dot(q) / det;
    if (v < 0.0 || u + v > 1.0) continue;
    if (e2.dot(q) / det > 0.0) ++n;
  }
  return n;
}

// Inside a closed mesh: an odd number of crossings along three skew rays (an open surface,
// a deck or a wall, is crossed an odd number of times along some rays only).
bool scene_file_point_inside(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0.0123, 0.0311, 1.0), Eigen::Vector3d(-0.0217, 0.0131, -1.0),
                                   Eigen::Vector3d(1.0, 0.0173, 0.0291)})
    if (scene_file_crossings(mesh, p, d.normalized()) % 2 == 0) return false;
  return true;
}

Result<Scene> load(const YAML::Node& root, const SceneInputs& in) {
  Scene s;
  s.name = root["name"] ? root["name"].as<std::string>() : in.default_name;
  s.seed = root["seed"] ? root["seed"].as<uint64_t>() : 0;
  if (root["vehicle_depth_m"]) s.vehicle_depth_m = root["vehicle_depth_m"].as<double>();
  if (root["seafloor_depth_m"]) s.seafloor_depth_m = root["seafloor_depth_m"].as<double>();
  if (!std::isfinite(s.vehicle_depth_m) || !std::isfinite(s.seafloor_depth_m))
    return Error{"vehicle_depth_m and seafloor_depth_m must be finite"};
  if (root["latitude_deg"]) s.latitude_deg = root["latitude_deg"].as<double>();
  if (!(s.latitude_deg >= -90.0 && s.latitude_deg <= 90.0))
    return Error{"latitude_deg: " + std::to_string(s.latitude_deg) + " is not a latitude in [-90, 90] degrees"};
  if (!(s.vehicle_depth_m < s.seafloor_depth_m))
    return Error{"vehicle_depth_m: " + std::to_string(s.vehicle_depth_m) + " m is not above the seafloor (seafloor_depth_m: " +
                 std::to_string(s.seafloor_depth_m) + " m): the mission would run under the seabed"};
  MeshBuilder b(s.mesh);
  uint32_t next_id = 1;
  if (const auto f = root["seafloor"]) {
    const double x0 = f["x_min_m"].as<double>(), x1 = f["x_max_m"].as<double>();
    const double y0 = f["y_min_m"].as<double>(), y1 = f["y_max_m"].as<double>();
    const double cell = f["cell_m"] ? f["cell_m"].as<double>() : 1.0;
    const double relief = f["relief_m"] ? f["relief_m"].as<double>() : 0.0;
    for (double v : {x0, x1, y0, y1, cell, relief})
      if (!std::isfinite(v)) return Error{"seafloor: x_min_m, x_max_m, y_min_m, y_max_m, cell_m and relief_m must be finite"};
    if (!(x1 > x0 && y1 > y0 && cell > 0)) return Error{"seafloor: empty extent or bad cell_m"};
    const double nx = std::ceil((x1 - x0) / cell), ny = std::ceil((y1 - y0) / cell);
    if (!(nx * ny <= kMaxSeafloorCells))
      return Error{"seafloor: " + std::to_string(nx) + " x " + std::to_string(ny) + " cells (extent / cell_m) exceed " +
                   std::to_string(static_cast<int64_t>(kMaxSeafloorCells)) + "; use a larger cell_m"};
    b.heightfield(x0, y0, static_cast<int>(nx), static_cast<int>(ny), cell,
                  seafloor_relief(s.seafloor_depth_m, relief, s.seed), {next_id++, SemanticClass::kSeafloor});
  }
  int index = 0;
  std::vector<std::pair<std::string, TriangleMesh>> placed;  // each object, for the start check
  for (const auto& o : root["objects"]) {
    const std::string where = "objects[" + std::to_string(index++) + "]";
    if (!o["mesh"]) return Error{where + ": no 'mesh'"};
    auto mesh = in.mesh(o["mesh"].as<std::string>());
    if (!mesh) return Error{where + ": " + mesh.error().message};
    const std::string cls = o["class"] ? o["class"].as<std::string>() : "other";
    if (cls != "from_file") {
      auto c = parse_class(cls);
      if (!c) return Error{where + ": " + c.error().message};
      const uint32_t id = o["object_id"] ? o["object_id"].as<uint32_t>() : next_id;
      next_id = std::max(next_id, id) + 1;
      std::fill(mesh->object_id.begin(), mesh->object_id.end(), id);
      std::fill(mesh->semantic.begin(), mesh->semantic.end(), *c);
    }
    double scale = o["scale"] ? o["scale"].as<double>() : 1.0;
    if (!(std::isfinite(scale) && scale > 0)) return Error{where + ": scale must be a finite number > 0"};
    SE3 T = SE3::Identity();
    if (const auto p = o["pose"]) {
      if (!p.IsSequence() || p.size() != 6) return Error{where + ": pose must be [x, y, z, roll_deg, pitch_deg, yaw_deg]"};
      constexpr double d = std::numbers::pi / 180.0;
      double v[6];
      for (int i = 0; i < 6; ++i) {
        v[i] = p[i].as<double>();
        if (!std::isfinite(v[i])) return Error{where + ": pose values must be finite"};
      }
      T = se3_from_xyz_rpy(v[0], v[1], v[2], v[3] * d, v[4] * d, v[5] * d);
    }
    if (scale != 1.0 || !T.matrix().isIdentity(0.0)) {
      for (auto& v : mesh->vertices) v = (T * (scale * v.cast<double>())).cast<float>();
    }
    s.mesh.append(*mesh);
    placed.emplace_back(where, std::move(*mesh));
  }
  if (root["route"] && root["route_file"]) return Error{"give either 'route' or 'route_file', not both"};
  if (const auto r = root["route"]) {
    for (const auto& w : r) {
      if (!w.IsSequence() || w.size() != 2) return Error{"route: each waypoint is [x, y]"};
      const Waypoint p{w[0].as<double>(), w[1].as<double>()};
      if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m)) return Error{"route: waypoints must be finite"};
      s.route.push_back(p);
    }
  } else if (root["route_file"]) {
    auto route = in.route_file(root["route_file"].as<std::string>());
    if (!route) return route.error();
    s.route = std::move(*route);
  }
  if (s.route.size() < 2) return Error{"the route needs at least two waypoints"};
  const std::string route_key = root["route"] ? "route" : "route_file";
  double route_length_m = 0.0;
  for (size_t i = 1; i < s.route.size(); ++i)
    route_length_m += std::hypot(s.route[i].x_m - s.route[i - 1].x_m, s.route[i].y_m - s.route[i - 1].y_m);
  if (!(route_length_m > 0.0))
    return Error{route_key + ": the waypoints are all at one point (route length 0 m); the route needs positive length"};
  const Eigen::Vector3d start(s.route[0].x_m, s.route[0].y_m, -s.vehicle_depth_m);
  for (const auto& [where, mesh] : placed)
    if (scene_file_point_inside(mesh, start))
      return Error{where + ": the vehicle starts inside this object (" + route_key + "[0] at vehicle_depth_m " +
                   std::to_string(s.vehicle_depth_m) + " m); move the object or the route"};
  if (s.mesh.triangles.empty()) return Error{"the scene has no triangles (no objects and no seafloor)"};
  if (!s.mesh.valid()) return Error{"the scene mesh is invalid"};
  return s;
}

// ---- embedded scenes: the mesh as binary PLY bytes, through mesh_io's in-memory codec
// (the same bytes write_mesh_ply writes, read by the one bounded PLY parser).
Result<std::vector<uint8_t>> ply_bytes(const TriangleMesh& mesh) {
  const std::string bytes = encode_mesh_ply(mesh);
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
}

Result<TriangleMesh> mesh_from_ply_bytes(const std::vector<uint8_t>& bytes, const std::string& name) {
  return decode_mesh_ply(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), name);
}

// Shortest text that reads back as the same double.
std::string exact(double v) {
  char b[40];
  for (int p = 15; p <= 17; ++p) {
    std::snprintf(b, sizeof b, "%.*g", p, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  return b;
}

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02x", c);
      q += b;
    } else {
      q += static_cast<char>(c);
    }
  }
  return q + "\"";
}

}  // namespace

Result<std::vector<EmbeddedFile>> embed_scene(const Scene& scene) {
  if (!scene.mesh.valid() || scene.mesh.triangles.empty()) return Error{"embed scene '" + scene.name + "': invalid mesh"};
  auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(scene.vehicle_depth_m) || !finite(scene.seafloor_depth_m))
    return Error{"embed scene '" + scene.name + "': non-finite depth"};
  std::string y;
  y += "# The scene this fixture was simulated in, embedded by orthosonar (docs/SCENES.md).\n";
  y += "# Saved beside " + std::string(kEmbeddedSceneMesh) + " it is a scene file (--scene-file).\n";
  y += "name: " + quoted(scene.name) + "\n";
  y += "origin: " + quoted(portable_origin(scene)) + "\n";
  y += "seed: " + std::to_string(scene.seed) + "\n";
  y += "vehicle_depth_m: " + exact(scene.vehicle_depth_m) + "\n";
  y += "seafloor_depth_m: " + exact(scene.seafloor_depth_m) + "\n";
  y += "classes: [";  // the mesh's per-face 'semantic' codes
  for (int c = 0; c < kSemanticClassCount; ++c)
    y += std::string(c == 0 ? "" : ", ") + semantic_class_name(static_cast<SemanticClass>(c));
  y += "]\n";
  y += "objects:\n  - mesh: " + std::string(kEmbeddedSceneMesh) + "\n    class: from_file\n";
  y += "route:\n";
  for (const auto& w : scene.route) {
    if (!finite(w.x_m) || !finite(w.y_m)) return Error{"embed scene '" + scene.name + "': non-finite waypoint"};
    y += "  - [" + exact(w.x_m) + ", " + exact(w.y_m) + "]\n";
  }
  auto ply = ply_bytes(scene.mesh);
  if (!ply) return Error{"embed scene '" + scene.name + "': " + ply.error().message};
  std::vector<EmbeddedFile> files;
  files.push_back({kEmbeddedSceneYaml, kEmbeddedSceneYamlType, std::vector<uint8_t>(y.begin(), y.end())});
  files.push_back({kEmbeddedSceneMesh, kEmbeddedSceneMeshType, std::move(*ply)});
  return files;
}

bool has_embedded_scene(const EmbeddedFiles& files) { return files.count(kEmbeddedSceneYaml) > 0; }

Result<Scene> scene_from_embedded(const EmbeddedFiles& files) {
  const std::string where = std::string("embedded scene (attachment ") + kEmbeddedSceneYaml + ")";
  const auto yaml = files.find(kEmbeddedSceneYaml);
  if (yaml == files.end()) return Error{where + ": missing"};
  SceneInputs in;
  in.default_name = "embedded";
  in.mesh = [&files](const std::string& name) -> Result<TriangleMesh> {
    const auto it = files.find(name);
    if (it == files.end()) return Error{"mesh '" + name + "' is not embedded in the fixture"};
    return mesh_from_ply_bytes(it->second, "attachment '" + name + "'");
  };
  in.route_file = [](const std::string& name) -> Result<std::vector<Waypoint>> {
    return Error{"route file '" + name + "' is not embedded in the fixture"};
  };
  try {
    const YAML::Node root = YAML::Load(std::string(yaml->second.begin(), yaml->second.end()));
    auto s = load(root, in);
    if (!s) return Error{where + ": " + s.error().message};
    s->origin = root["origin"] ? root["origin"].as<std::string>() : s->name;
    return s;
  } catch (const YAML::Exception& e) {
    return Error{where + ": " + e.what()};
  }
}

Result<Scene> load_scene_file(const std::string& yaml_path) {
  const fs::path path = fs::absolute(yaml_path).lexically_normal();
  const fs::path dir = path.parent_path();
  auto resolve = [dir](const std::string& p) { return (fs::path(p).is_absolute() ? fs::path(p) : dir / p).string(); };
  SceneInputs in;
  in.default_name = path.stem().string();
  in.mesh = [resolve](const std::string& p) { return read_mesh(resolve(p)); };
  in.route_file = [resolve](const std::string& p) { return read_route_csv(resolve(p)); };
  try {
    auto s = load(YAML::LoadFile(path.string()), in);
    if (!s) return Error{"scene file '" + yaml_path + "': " + s.error().message};
    s->origin = "file:" + path.string();
    return s;
  } catch (const YAML::Exception& e) {
    return Error{"scene file '" + yaml_path + "': " + e.what()};
  }
}

}  // namespace orthosonar::sim
