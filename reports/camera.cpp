#include "reports/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace orthosonar::reports {

Bounds scene_bounds(const TriangleMesh* mesh, const Trajectory* truth, const std::vector<Eigen::Vector3f>& fallback,
                    const SceneBoundsConfig& config) {
  Bounds traj;
  if (truth)
    for (const auto& p : *truth) traj.extend(p.position);
  Bounds box;  // horizontal region of interest
  if (mesh && !mesh->triangles.empty()) {
    Bounds structures;
    for (size_t i = 0; i < mesh->triangles.size(); ++i) {
      if (mesh->semantic[i] == SemanticClass::kSeafloor) continue;
      for (int c = 0; c < 3; ++c) structures.extend(mesh->vertices[static_cast<size_t>(mesh->triangles[i][c])].cast<double>());
    }
    if (!structures.valid())  // only seafloor: the whole mesh
      for (const auto& v : mesh->vertices) structures.extend(v.cast<double>());
    box = structures;
    if (traj.valid()) {
      const Eigen::Vector3d m(config.reach_m, config.reach_m, 0.0);
      box.min.head<2>() = box.min.head<2>().cwiseMax((traj.min - m).head<2>());
      box.max.head<2>() = box.max.head<2>().cwiseMin((traj.max + m).head<2>());
      if (!box.valid()) box = traj;  // structures nowhere near the mission
      box.extend(traj.min);
      box.extend(traj.max);
    }
    // z: the mesh (seafloor included) inside the horizontal box.
    Bounds z;
    for (const auto& v : mesh->vertices) {
      const Eigen::Vector3d p = v.cast<double>();
      if (p.x() >= box.min.x() && p.x() <= box.max.x() && p.y() >= box.min.y() && p.y() <= box.max.y()) z.extend(p);
    }
    if (!z.valid())
      for (const auto& v : mesh->vertices) z.extend(v.cast<double>());
    box.min.z() = std::min(box.min.z(), z.min.z());
    box.max.z() = std::max(box.max.z(), z.max.z());
    const double top = config.surface_z_m + config.above_surface_m;
    if (box.min.z() < top) box.max.z() = std::min(box.max.z(), top);
    return box;
  }
  if (traj.valid()) {
    // No mesh: a box around the track, deep enough for a seafloor.
    box = traj;
    box.min -= Eigen::Vector3d(10.0, 10.0, 10.0);
    box.max += Eigen::Vector3d(10.0, 10.0, 1.0);
    return box;
  }
  for (const auto& p : fallback) box.extend(p.cast<double>());
  return box;
}

Camera fixed_camera(const Bounds& bounds, View view, double aspect) {
  Camera cam;
  const Eigen::Vector3d c = bounds.centre();
  const Eigen::Vector3d s = bounds.size().cwiseMax(Eigen::Vector3d::Constant(1.0));
  cam.focal_point = c;
  if (view == View::kTop) {
    cam.parallel = true;
    cam.position = c + Eigen::Vector3d(0.0, 0.0, s.z() + 2.0 * s.norm());
    cam.view_up = Eigen::Vector3d::UnitY();
    // Room on the right for the colour bar, a margin all round.
    cam.parallel_scale_m = 0.55 * std::max(s.y(), s.x() / (0.85 * aspect));
    cam.focal_point.x() += 0.05 * 2.0 * cam.parallel_scale_m * aspect;
    cam.position.x() = cam.focal_point.x();
    return cam;
  }
  const double az = -35.0 * std::numbers::pi / 180.0;  // from -y towards -x
  const double el = 35.0 * std::numbers::pi / 180.0;
  const Eigen::Vector3d dir(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
  const double radius = 0.5 * s.norm();
  const double half_fov = 0.5 * cam.view_angle_deg * std::numbers::pi / 180.0;
  const double distance = 0.85 * radius / std::sin(half_fov);
  cam.position = c + distance * dir;
  cam.view_up = Eigen::Vector3d::UnitZ();
  return cam;
}

}  // namespace orthosonar::reports
