#include "core/inference/object_registry.hpp"

#include <algorithm>
#include <cmath>

namespace orthosonar::inference {

SightingFrame sighting_frame(const std::vector<double>& ranges_m, const std::vector<double>& bearings_rad) {
  SightingFrame f;
  if (ranges_m.empty() || bearings_rad.empty()) return f;
  f.range_min_m = *std::min_element(ranges_m.begin(), ranges_m.end());
  std::vector<double> b = bearings_rad;
  const size_t mid = (b.size() - 1) / 2;
  std::nth_element(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(mid), b.end());
  f.bearing_median_rad = b[mid];
  return f;
}

Vec2 to_sighting(const SightingFrame& frame, double range_m, double bearing_rad) {
  const double a = bearing_rad - frame.bearing_median_rad;
  return {range_m * std::cos(a) - frame.range_min_m, range_m * std::sin(a)};
}

std::optional<Registration> ClassReference::register_sighting(const std::vector<Vec2>& points_obj) {
  Registration r;
  if (points_.empty()) {
    r.first_sighting = true;
    add(points_obj);
    return r;
  }
  const slam::IcpResult icp = slam::icp_2d(points_obj, points_, SE2::identity(), config_.icp);
  if (!icp.converged || icp.rmse > config_.max_rmse_m ||
      icp.T_target_source.translation().norm() > config_.max_translation_m) {
    return std::nullopt;
  }
  r.T_ref_obj = icp.T_target_source;
  r.iterations = icp.iterations;
  r.rmse_m = icp.rmse;
  return r;
}

void ClassReference::add(const std::vector<Vec2>& points_ref) {
  for (const Vec2& p : points_ref) {
    if (points_.size() >= config_.max_reference_points) return;
    const std::pair<long, long> key{static_cast<long>(std::floor(p.x() / config_.reference_voxel_m)),
                                    static_cast<long>(std::floor(p.y() / config_.reference_voxel_m))};
    if (voxels_.insert(key).second) points_.push_back(p);
  }
}

}  // namespace orthosonar::inference
