#include "reports/map_views.hpp"

#include <algorithm>

#include "core/mapping/mesh_distance.hpp"
#include "reports/nearest.hpp"

namespace orthosonar::reports {

const char* view_name(View view) { return view == View::kTop ? "top" : "oblique"; }

Bounds run_bounds(const RunData& run) {
  std::vector<Eigen::Vector3f> fallback;
  for (const auto& s : run.systems) fallback.insert(fallback.end(), s.map_W.begin(), s.map_W.end());
  return scene_bounds(run.mesh ? &*run.mesh : nullptr, run.truth ? &*run.truth : nullptr, fallback);
}

std::pair<double, double> height_range(const Bounds& bounds) {
  if (!bounds.valid()) return {0.0, 1.0};
  return {bounds.min.z(), std::max(bounds.max.z(), bounds.min.z() + 0.1)};
}

namespace {

std::vector<RenderTrajectory> trajectories_of(const RunData& run) {
  std::vector<RenderTrajectory> out;
  auto add = [&](const std::optional<Trajectory>& t, const char* label, Rgb colour) {
    if (!t || t->size() < 2) return;
    RenderTrajectory r;
    r.label = label;
    r.colour = colour;
    for (const auto& p : *t) r.points_W.push_back(p.position);
    out.push_back(std::move(r));
  };
  add(run.truth, "ground truth", truth_colour());
  add(run.dr, "dead reckoning", dr_colour());
  add(run.slam, "SLAM", slam_colour());
  return out;
}

}  // namespace

Result<cv::Mat> render_map_view(const RunData& run, const std::vector<Eigen::Vector3f>& map_W, View view,
                                const Bounds& bounds, const std::string& title, const RenderConfig& config) {
  if (!bounds.valid()) return Error{"render: nothing to frame (no mesh, trajectory or points)"};
  RenderScene scene;
  scene.points_W = map_W;
  scene.scalar_range = height_range(bounds);
  scene.mesh = run.mesh ? &*run.mesh : nullptr;
  scene.trajectories = trajectories_of(run);
  scene.title = title;
  const double aspect = static_cast<double>(config.width_px) / config.height_px;
  return render_scene(scene, fixed_camera(bounds, view, aspect), config);
}

Result<cv::Mat> render_difference_view(const RunData& run, const std::vector<Eigen::Vector3f>& current_W,
                                       const std::vector<Eigen::Vector3f>& reference_W, double max_distance_m,
                                       View view, const Bounds& bounds, const std::string& title,
                                       const RenderConfig& config) {
  if (!bounds.valid()) return Error{"render: nothing to frame (no mesh, trajectory or points)"};
  RenderScene scene;
  scene.points_W = current_W;
  scene.scalars = nearest_distances(current_W, reference_W, max_distance_m);
  scene.colour_map = ColourMap::kDistance;
  scene.scalar_title = "distance (m)";
  scene.scalar_range = std::make_pair(0.0, max_distance_m);
  scene.mesh = run.mesh ? &*run.mesh : nullptr;
  scene.title = title;
  const double aspect = static_cast<double>(config.width_px) / config.height_px;
  return render_scene(scene, fixed_camera(bounds, view, aspect), config);
}

Result<cv::Mat> render_mesh_error_view(const RunData& run, const std::vector<Eigen::Vector3f>& map_W,
                                       double max_distance_m, View view, const Bounds& bounds,
                                       const std::string& title, const RenderConfig& config) {
  if (!bounds.valid()) return Error{"render: nothing to frame (no mesh, trajectory or points)"};
  if (!run.mesh || run.mesh->triangles.empty()) return Error{"distance to the mesh: the run has no truth mesh"};
  const mapping::MeshDistance mesh(*run.mesh);
  RenderScene scene;
  scene.points_W = map_W;
  scene.scalars.reserve(map_W.size());
  for (const auto& p : map_W)
    scene.scalars.push_back(static_cast<float>(std::min(mesh.distance(p.cast<double>()), max_distance_m)));
  scene.colour_map = ColourMap::kDistance;
  scene.scalar_title = "distance to mesh (m)";
  scene.scalar_range = std::make_pair(0.0, max_distance_m);
  scene.mesh = &*run.mesh;
  scene.trajectories = trajectories_of(run);
  scene.title = title;
  const double aspect = static_cast<double>(config.width_px) / config.height_px;
  return render_scene(scene, fixed_camera(bounds, view, aspect), config);
}

}  // namespace orthosonar::reports
