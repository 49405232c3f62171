#include "hal/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "hal/sim/scenes_builtin.hpp"

namespace orthosonar::sim {
namespace detail {

void SceneAssembly::seafloor(double x0, double x1, double y0, double y1, double relief_m) {
  floor_z = seafloor_relief(scene.seafloor_depth_m, relief_m, scene.seed);
  const int nx = static_cast<int>(std::ceil(x1 - x0));
  const int ny = static_cast<int>(std::ceil(y1 - y0));
  b.heightfield(x0, y0, nx, ny, 1.0, floor_z, next(SemanticClass::kSeafloor));
}

void SceneAssembly::piling(double x, double y, double radius_m) {
  const double bottom = floor_z ? floor_z(x, y) - 0.5 : -scene.seafloor_depth_m - 0.5;
  b.cylinder({x, y, bottom}, {x, y, 1.5}, radius_m, 12, next(SemanticClass::kPiling));
}

void SceneAssembly::dock(const Vec2& c, const Vec2& size, double yaw, double draft_m) {
  const double freeboard = 0.4;
  b.box({c.x(), c.y(), 0.5 * (freeboard - draft_m)}, {size.x(), size.y(), freeboard + draft_m}, yaw,
        next(SemanticClass::kDock));
}

void SceneAssembly::debris(int count, double x0, double x1, double y0, double y1, double min_clear_m,
                           uint64_t stream) {
  Rng rng(derive_seed(scene.seed, stream));
  int placed = 0;
  for (int attempt = 0; placed < count && attempt < 50 * count; ++attempt) {
    const double x = rng.uniform(x0, x1), y = rng.uniform(y0, y1);
    const double r = rng.uniform(0.25, 0.8);
    bool clear = true;
    for (size_t i = 0; i + 1 < scene.route.size() && clear; ++i) {
      const Vec2 a(scene.route[i].x_m, scene.route[i].y_m), bb(scene.route[i + 1].x_m, scene.route[i + 1].y_m);
      const Vec2 p(x, y);
      const double t = std::clamp((p - a).dot(bb - a) / std::max(1e-9, (bb - a).squaredNorm()), 0.0, 1.0);
      clear = (a + t * (bb - a) - p).norm() >= min_clear_m;
    }
    if (!clear) continue;
    b.rock({x, y, floor_z(x, y) + 0.3 * r}, r, rng, next(SemanticClass::kOther));
    ++placed;
  }
}

}  // namespace detail

Status select_route(Scene& scene, const std::string& name) {
  if (name.empty() || name == "default") return {};
  for (const auto& r : scene.routes) {
    if (r.name != name) continue;
    scene.route = r.waypoints;
    scene.route_name = r.name;
    return {};
  }
  std::string known = "default";
  for (const auto& r : scene.routes) known += ", " + r.name;
  return Error{"route '" + name + "' is not a route of scene '" + scene.name + "' (its routes: " + known + ")"};
}

namespace {

// The built-in scenes' named routes, one table for the scenes and the names.
struct BuiltinRoute {
  const char* scene;
  const char* name;
  std::vector<Waypoint> (*waypoints)();
};
const BuiltinRoute kBuiltinRoutes[] = {{"harbor", "survey", detail::harbor_survey_route}};

}  // namespace

std::vector<std::string> builtin_route_names(const std::string& scene) {
  std::vector<std::string> out;
  for (const auto& r : kBuiltinRoutes)
    if ((scene.empty() || scene == r.scene) && std::find(out.begin(), out.end(), r.name) == out.end())
      out.push_back(r.name);
  return out;
}

std::vector<std::string> builtin_scene_names() { return {"marina1", "marina2", "harbor", "aircraft"}; }

Result<Scene> builtin_scene(const std::string& name, uint64_t seed) {
  Scene s;
  if (name == "marina1") s = detail::build_marina1(seed);
  else if (name == "marina2") s = detail::build_marina2(seed);
  else if (name == "harbor") s = detail::build_harbor(seed);
  else if (name == "aircraft") s = detail::build_aircraft(seed);
  else return Error{"unknown scene '" + name + "' (built-in: marina1, marina2, harbor, aircraft)"};
  s.name = name;
  s.seed = seed;
  s.origin = name;
  for (const auto& r : kBuiltinRoutes)
    if (name == r.scene) s.routes.push_back({r.name, r.waypoints()});
  return s;
}

Result<Scene> scene_from_metadata(const std::map<std::string, std::string>& md) {
  const auto it = md.find("scene");
  if (it == md.end()) return Error{"fixture metadata has no 'scene' key"};
  if (it->second.rfind("file:", 0) == 0) {
    const std::string path = it->second.substr(5);
    if (!std::filesystem::path(path).is_absolute())
      return Error{"fixture metadata names scene file '" + path +
                   "' without its folder and the fixture has no embedded scene (attachment " +
                   kEmbeddedSceneYaml + ")"};
    return load_scene_file(path);
  }
  auto seed_it = md.find("scene_seed");
  if (seed_it == md.end()) seed_it = md.find("seed");
  uint64_t seed = 0;
  if (seed_it != md.end()) {
    try {
      seed = std::stoull(seed_it->second);
    } catch (const std::exception&) {
      return Error{"fixture metadata: bad seed '" + seed_it->second + "'"};
    }
  }
  return builtin_scene(it->second, seed);
}

std::string portable_origin(const Scene& scene) {
  if (scene.origin.rfind("file:", 0) == 0)
    return "file:" + std::filesystem::path(scene.origin.substr(5)).filename().string();
  return scene.origin.empty() ? scene.name : scene.origin;
}

Result<Scene> scene_from_fixture(const std::map<std::string, std::string>& md, const EmbeddedFiles& files,
                                 bool* embedded) {
  const bool has = has_embedded_scene(files);
  if (embedded != nullptr) *embedded = has;
  if (has) return scene_from_embedded(files);
  return scene_from_metadata(md);
}

}  // namespace orthosonar::sim
