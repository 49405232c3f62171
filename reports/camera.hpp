#pragma once
// A fixed camera per scene, computed from the scene (ground-truth mesh, truth
// trajectory), never from the map cloud, so renders of different runs of the same scene
// are directly comparable pixel by pixel.
#include <vector>

#include <Eigen/Core>

#include "core/mesh.hpp"
#include "reports/run_data.hpp"

namespace orthosonar::reports {

struct Bounds {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-1e300);
  bool valid() const { return (min.array() <= max.array()).all(); }
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  Eigen::Vector3d centre() const { return 0.5 * (min + max); }
  Eigen::Vector3d size() const { return max - min; }
};

struct SceneBoundsConfig {
  // Horizontal reach around the truth trajectory: the sonars' range, so every structure
  // that can appear in a map is in view and nothing farther.
  double reach_m = 30.0;
  // World z = 0 is the water surface; masts and superstructure above it are never
  // sensed, so the view stops `above_surface_m` over it.
  double surface_z_m = 0.0;
  double above_surface_m = 1.0;
};

// The region to show: structures of the mesh (triangles that are not seafloor) and the
// truth trajectory, horizontally clipped to the trajectory's box grown by reach_m when
// the mesh is larger (a long seawall); z spans the mesh inside that box, capped just
// above the surface. Without a mesh, the truth trajectory grown by a few metres; with
// neither, `fallback` (e.g. a map cloud). Invalid if all are empty.
Bounds scene_bounds(const TriangleMesh* mesh, const Trajectory* truth, const std::vector<Eigen::Vector3f>& fallback,
                    const SceneBoundsConfig& config = {});

enum class View { kTop, kOblique };

struct Camera {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d focal_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d view_up = Eigen::Vector3d::UnitZ();
  bool parallel = false;
  double parallel_scale_m = 1.0;  // half the visible height, parallel projection
  double view_angle_deg = 30.0;   // vertical field of view, perspective
};

// Top: orthographic, looking down -z, north (+y) up. Oblique: perspective from the
// south-west, 35 degrees above the horizon, the whole box in view. aspect = width/height.
Camera fixed_camera(const Bounds& bounds, View view, double aspect);

}  // namespace orthosonar::reports
