#include "core/slam/planar_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "core/slam/icp.hpp"

namespace orthosonar::slam {

std::vector<Eigen::Vector2d> voxel_downsample(const std::vector<Eigen::Vector2d>& points,
                                              double voxel_m) {
  struct Keyed {
    long long kx, ky;
    size_t index;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    keyed.push_back({static_cast<long long>(std::floor(points[i].x() / voxel_m)),
                     static_cast<long long>(std::floor(points[i].y() / voxel_m)), i});
  }
  // Sorted voxel keys; inside a voxel, input order (so the centroid sum is reproducible).
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    if (a.kx != b.kx) return a.kx < b.kx;
    if (a.ky != b.ky) return a.ky < b.ky;
    return a.index < b.index;
  });
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < keyed.size();) {
    size_t j = i;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    while (j < keyed.size() && keyed[j].kx == keyed[i].kx && keyed[j].ky == keyed[i].ky) {
      sum += points[keyed[j].index];
      ++j;
    }
    out.push_back(sum / static_cast<double>(j - i));
    i = j;
  }
  return out;
}

std::vector<Eigen::Vector2d> remove_radius_outliers(const std::vector<Eigen::Vector2d>& points,
                                                    double radius_m, size_t min_neighbours) {
  const Grid2d grid(points, radius_m);
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    // count_within includes the point itself.
    if (grid.count_within(p, radius_m) >= min_neighbours + 1) out.push_back(p);
  }
  return out;
}

bool in_sonar_view(const Eigen::Vector2d& p_view, double range_m, double fov_deg, double sonar_x_m) {
  const Eigen::Vector2d q = p_view - Eigen::Vector2d(sonar_x_m, 0.0);
  return q.norm() <= range_m &&
         std::abs(std::atan2(q.y(), q.x())) <= 0.5 * fov_deg * std::numbers::pi / 180.0;
}

std::vector<Eigen::Vector2d> gate_to_sonar_view(const std::vector<Eigen::Vector2d>& points_F,
                                                const SE2& T_view_F, double range_m,
                                                double fov_deg, double sonar_x_m) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& p : points_F) {
    if (in_sonar_view(T_view_F * p, range_m, fov_deg, sonar_x_m)) out.push_back(p);
  }
  return out;
}

std::vector<Eigen::Vector2d> prepare_planar_cloud(const std::vector<Eigen::Vector2d>& points,
                                                  const PlanarCloudConfig& config) {
  return remove_radius_outliers(voxel_downsample(points, config.voxel_m), config.outlier_radius_m,
                                config.outlier_min_neighbours);
}

}  // namespace orthosonar::slam
