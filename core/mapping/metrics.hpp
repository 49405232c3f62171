#pragma once
// Map metrics (SPEC §7): coverage as occupied 0.1 m voxels, accuracy as the exact
// point-to-triangle distance from every voxel centroid to the ground-truth mesh, and the
// absolute trajectory error of keyframe positions.
#include <cstdint>
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/mapping/mesh_distance.hpp"
#include "core/time.hpp"

namespace orthosonar::mapping {

struct VoxelConfig {
  double voxel_m = 0.1;
};

// One centroid per occupied voxel (index floor(x / voxel_m)), ordered by voxel index
// (x, then y, then z). The result is bit-identical for any order of the input points.
std::vector<Eigen::Vector3f> voxel_centroids(const std::vector<Eigen::Vector3f>& points,
                                             const VoxelConfig& config = {});
// Number of occupied voxels.
int64_t coverage_voxels(const std::vector<Eigen::Vector3f>& points, const VoxelConfig& config = {});

struct AccuracyStats {
  int64_t count = 0;
  double mae_m = 0.0;
  double rmse_m = 0.0;
};
// MAE and RMSE of the distances from each point to the mesh (sums in point order).
AccuracyStats accuracy(const std::vector<Eigen::Vector3f>& points, const MeshDistance& mesh);

// A timed position.
struct StampedPosition {
  Time stamp;
  Vec3 p_W = Vec3::Zero();
};
// A truth pose as T_W_V (through the rotation matrix of its normalised quaternion).
SE3 truth_pose(const TruthPose& p);
// Ground truth p_W at `t`, linearly interpolated between the neighbouring truth poses
// (sorted by stamp); nullopt outside their span.
std::optional<Vec3> truth_position_at(const std::vector<TruthPose>& truth, Time t);
// Ground truth T_W_V at `t`: position as truth_position_at, orientation slerped between
// the neighbouring truth poses; nullopt outside their span.
std::optional<SE3> truth_pose_at(const std::vector<TruthPose>& truth, Time t);
// Truth poses as they arrive in a stream (stamp order; a pose of an earlier stamp is
// inserted in place, one of a stamp already held replaces it), kept only as far back as a
// later question needs: truth_pose_at over a sliding window, for a consumer that cannot
// hold a whole mission's truth (perception_metrics.hpp).
class TruthTrack {
 public:
  void add(const TruthPose& p);
  // truth_pose_at(t) over the poses held, and at either end of them the nearest pose
  // (held, not extrapolated); nullopt when none is held.
  std::optional<SE3> at(Time t) const;
  // Forgets every pose but the last one at or before t (and those after it): at() stays
  // the same for every stamp >= t.
  void forget_before(Time t);
  bool empty() const { return poses_.empty(); }
  // Stamp of the latest pose held (empty(): undefined).
  Time last_stamp() const { return poses_.back().stamp; }
  size_t size() const { return poses_.size(); }

 private:
  std::vector<TruthPose> poses_;  // sorted by stamp, unique stamps
};
// RMSE of estimate positions against truth interpolated at their stamps. Estimates outside
// the truth span are skipped; nullopt when none remain.
std::optional<double> absolute_trajectory_error(const std::vector<StampedPosition>& estimate,
                                                const std::vector<TruthPose>& truth);

// A timed pose (keyframes' DR or SLAM estimate).
struct StampedPose {
  Time stamp;
  SE3 T_W_V = SE3::Identity();
};
// Heading error against truth (issue 33): for every estimate inside the truth span, the
// yaw of the estimate minus the yaw of the truth pose slerped to its stamp, wrapped to
// (-180, 180] degrees, with no alignment (like the ATE: the heading reference's drift is
// part of the error). Estimates outside the truth span are skipped.
struct HeadingErrorStats {
  int64_t count = 0;
  double rms_deg = 0.0;
  double mean_deg = 0.0;     // the signed mean (a bias the graph did not remove)
  double max_abs_deg = 0.0;
};
// nullopt when no estimate is inside the truth span.
std::optional<HeadingErrorStats> heading_error(const std::vector<StampedPose>& estimate,
                                               const std::vector<TruthPose>& truth);

}  // namespace orthosonar::mapping
