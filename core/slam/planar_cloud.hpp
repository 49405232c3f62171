#pragma once
// Planar cloud preparation for SLAM (SPEC §5): voxel downsampling and radius outlier
// removal, both deterministic (sorted voxel keys, input-order sums).
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/geometry.hpp"

namespace orthosonar::slam {

struct PlanarCloudConfig {
  double voxel_m = 0.5;
  double outlier_radius_m = 1.0;
  size_t outlier_min_neighbours = 5;  // other points within the radius
};

// One centroid per occupied voxel (index = floor(p / voxel_m)), voxels in sorted key order.
std::vector<Eigen::Vector2d> voxel_downsample(const std::vector<Eigen::Vector2d>& points,
                                              double voxel_m);
// Keeps points with at least min_neighbours other points within radius_m; order preserved.
std::vector<Eigen::Vector2d> remove_radius_outliers(const std::vector<Eigen::Vector2d>& points,
                                                    double radius_m, size_t min_neighbours);
// Field-of-view gating: the points (given in some frame F) that a horizontal sonar at
// sonar_x_m along x of the view frame could see, where T_view_F maps F into the view frame:
// range <= range_m and |bearing| <= fov_deg / 2. Order preserved.
std::vector<Eigen::Vector2d> gate_to_sonar_view(const std::vector<Eigen::Vector2d>& points_F,
                                                const SE2& T_view_F, double range_m,
                                                double fov_deg, double sonar_x_m);
bool in_sonar_view(const Eigen::Vector2d& p_view, double range_m, double fov_deg, double sonar_x_m);

// Voxel downsample then outlier removal.
std::vector<Eigen::Vector2d> prepare_planar_cloud(const std::vector<Eigen::Vector2d>& points,
                                                  const PlanarCloudConfig& config);

}  // namespace orthosonar::slam
