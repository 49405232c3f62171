// User scenes from YAML (docs/SCENES.md): mesh files placed by poses, classes, an optional
// generated seafloor, and a route inline or in a CSV file.
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
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

Result<Scene> load(const fs::path& yaml_path) {
  const YAML::Node root = YAML::LoadFile(yaml_path.string());
  const fs::path dir = yaml_path.parent_path();
  auto resolve = [&dir](const std::string& p) { return fs::path(p).is_absolute() ? fs::path(p) : dir / p; };
  Scene s;
  s.name = root["name"] ? root["name"].as<std::string>() : yaml_path.stem().string();
  s.seed = root["seed"] ? root["seed"].as<uint64_t>() : 0;
  if (root["vehicle_depth_m"]) s.vehicle_depth_m = root["vehicle_depth_m"].as<double>();
  if (root["seafloor_depth_m"]) s.seafloor_depth_m = root["seafloor_depth_m"].as<double>();
  MeshBuilder b(s.mesh);
  uint32_t next_id = 1;
  if (const auto f = root["seafloor"]) {
    const double x0 = f["x_min_m"].as<double>(), x1 = f["x_max_m"].as<double>();
    const double y0 = f["y_min_m"].as<double>(), y1 = f["y_max_m"].as<double>();
    const double cell = f["cell_m"] ? f["cell_m"].as<double>() : 1.0;
    const double relief = f["relief_m"] ? f["relief_m"].as<double>() : 0.0;
    if (!(x1 > x0 && y1 > y0 && cell > 0)) return Error{"seafloor: empty extent or bad cell_m"};
    b.heightfield(x0, y0, static_cast<int>(std::ceil((x1 - x0) / cell)), static_cast<int>(std::ceil((y1 - y0) / cell)),
                  cell, seafloor_relief(s.seafloor_depth_m, relief, s.seed), {next_id++, SemanticClass::kSeafloor});
  }
  int index = 0;
  for (const auto& o : root["objects"]) {
    const std::string where = "objects[" + std::to_string(index++) + "]";
    if (!o["mesh"]) return Error{where + ": no 'mesh'"};
    auto mesh = read_mesh(resolve(o["mesh"].as<std::string>()).string());
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
    SE3 T = SE3::Identity();
    if (const auto p = o["pose"]) {
      if (!p.IsSequence() || p.size() != 6) return Error{where + ": pose must be [x, y, z, roll_deg, pitch_deg, yaw_deg]"};
      constexpr double d = std::numbers::pi / 180.0;
      T = se3_from_xyz_rpy(p[0].as<double>(), p[1].as<double>(), p[2].as<double>(), p[3].as<double>() * d,
                           p[4].as<double>() * d, p[5].as<double>() * d);
    }
    if (scale != 1.0 || !T.matrix().isIdentity(0.0)) {
      for (auto& v : mesh->vertices) v = (T * (scale * v.cast<double>())).cast<float>();
    }
    s.mesh.append(*mesh);
  }
  if (root["route"] && root["route_file"]) return Error{"give either 'route' or 'route_file', not both"};
  if (const auto r = root["route"]) {
    for (const auto& w : r) {
      if (!w.IsSequence() || w.size() != 2) return Error{"route: each waypoint is [x, y]"};
      s.route.push_back({w[0].as<double>(), w[1].as<double>()});
    }
  } else if (root["route_file"]) {
    auto route = read_route_csv(resolve(root["route_file"].as<std::string>()).string());
    if (!route) return route.error();
    s.route = std::move(*route);
  }
  if (s.route.size() < 2) return Error{"the route needs at least two waypoints"};
  if (s.mesh.triangles.empty()) return Error{"the scene has no triangles (no objects and no seafloor)"};
  if (!s.mesh.valid()) return Error{"the scene mesh is invalid"};
  return s;
}

}  // namespace

Result<Scene> load_scene_file(const std::string& yaml_path) {
  const fs::path path = fs::absolute(yaml_path).lexically_normal();
  try {
    auto s = load(path);
    if (!s) return Error{"scene file '" + yaml_path + "': " + s.error().message};
    s->origin = "file:" + path.string();
    return s;
  } catch (const YAML::Exception& e) {
    return Error{"scene file '" + yaml_path + "': " + e.what()};
  }
}

}  // namespace orthosonar::sim
