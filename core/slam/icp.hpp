#pragma once
// 2D point-to-point ICP with trimming (SPEC §5; point-to-line as an option), deterministic:
// nearest neighbours from a sorted uniform grid, correspondences trimmed by distance with
// index tie-breaks.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry.hpp"

namespace orthosonar::slam {

struct IcpConfig {
  // What each iteration minimises (docs/SLAM.md "Heading drift on the AHRS", tried and not
  // a default: it did not move the sonar matches' heading error): the squared
  // distance to the nearest target point (SPEC §5, Besl & McKay 1992), or, where the target
  // is locally a line, the squared distance to that line (Censi 2008, "An ICP variant using
  // a point-to-line metric"; isolated points keep point-to-point rows). A wall's voxel
  // centroids are then not pulled along it to the other cloud's centroids.
  enum class Metric : uint8_t { kPointToPoint, kPointToLine };
  Metric metric = Metric::kPointToPoint;
  double line_radius_m = 1.0;  // point-to-line: target neighbourhood of a line's normal
  double line_ratio = 0.1;     // ...PCA eigenvalue ratio below which it is a line
  int max_iterations = 40;
  double max_correspondence_m = 3.0;
  double trim_fraction = 0.8;          // keep the best fraction of source points' matches...
  // ...but never trim a match closer than this. Pure fractional trimming has wrong fixed
  // points: at a slightly wrong pose it discards exactly the matches that would pull it back.
  double trim_floor_m = 0.5;
  double converged_translation_m = 1e-4;  // stop when an update moves less than this
  double converged_rotation_rad = 1e-5;   // ... and rotates less than this
  size_t min_correspondences = 10;
  bool accelerate = true;  // Besl & McKay (1992) extrapolation of aligned successive steps
  // Translation only: the rotation stays the initial guess's (a heading known better than
  // the fit could find it, e.g. a FOG's: keyframe_slam.hpp nssm_fixed_heading_gyro).
  bool fix_rotation = false;
};

constexpr IcpConfig::Metric kIcpMetrics[] = {IcpConfig::Metric::kPointToPoint, IcpConfig::Metric::kPointToLine};
constexpr const char* icp_metric_name(IcpConfig::Metric m) {
  return m == IcpConfig::Metric::kPointToLine ? "point_to_line" : "point_to_point";
}

struct IcpResult {
  SE2 T_target_source;  // maps source points into the target frame
  bool converged = false;
  int iterations = 0;
  size_t inliers = 0;   // correspondences kept at the last iteration
  double rmse = 0.0;    // over the kept correspondences, metres
};

// Aligns `source` to `target` starting from `initial` (T_target_source guess).
IcpResult icp_2d(const std::vector<Eigen::Vector2d>& source,
                 const std::vector<Eigen::Vector2d>& target, const SE2& initial,
                 const IcpConfig& config);

// What a scan match observes (Censi 2007; Zhang, Kaess & Singh 2016, "On degeneracy of
// optimization-based state estimation problems"): the Gauss-Newton Hessian H = Σ JᵀJ of the
// fit at its solution, in (x, y, θ) of T_target_source. Each kept correspondence contributes
// point-to-line (one row, along the target's local normal) where the target is locally a
// line (PCA of its points within normal_radius_m: smaller/larger eigenvalue below
// line_ratio), else point-to-point (two rows: an isolated piling constrains both
// directions). A straight wall leaves translation along it unobserved: H has a near-zero
// eigenvalue there, which the SLAM factor then does not constrain (keyframe_slam.cpp).
struct FitInformationConfig {
  double max_correspondence_m = 1.0;  // correspondences used (the converged fit's inliers)
  double normal_radius_m = 1.0;       // target neighbourhood of a normal (2 voxels of 0.5 m)
  double line_ratio = 0.1;            // PCA eigenvalue ratio below which the neighbourhood is a line
};
struct FitInformation {
  Eigen::Matrix3d hessian = Eigen::Matrix3d::Zero();
  size_t correspondences = 0;
  size_t line_rows = 0;   // correspondences on a locally straight target
};
FitInformation icp_fit_information(const std::vector<Eigen::Vector2d>& source,
                                   const std::vector<Eigen::Vector2d>& target, const SE2& T_target_source,
                                   const FitInformationConfig& config = {});

// Nearest-neighbour index over 2D points within a fixed radius (grid of radius-sized cells,
// stored sorted; no hashing). Ties between equidistant points go to the lower index.
class Grid2d {
 public:
  Grid2d(const std::vector<Eigen::Vector2d>& points, double cell_m);
  // Index of the nearest point within max_dist, or -1.
  long nearest(const Eigen::Vector2d& q, double max_dist, double* dist2 = nullptr) const;
  // Number of points within radius of q (q itself counts if it is one of the points).
  size_t count_within(const Eigen::Vector2d& q, double radius) const;
  // Indices of the points within radius of q, ascending.
  std::vector<long> within(const Eigen::Vector2d& q, double radius) const;

 private:
  struct Entry {
    long long cx, cy;
    long index;
  };
  template <class F>
  void for_cell(long long cx, long long cy, F&& f) const;
  // f(index) for every point within radius of q (grid order).
  template <class F>
  void for_each_within(const Eigen::Vector2d& q, double radius, F&& f) const;
  const std::vector<Eigen::Vector2d>* points_;
  double cell_m_;
  std::vector<Entry> entries_;  // sorted by (cx, cy, index)
  // When the occupied cells' bounding box is small (the usual scan), the entries of cell
  // (cx, cy) are entries_[starts_[k], starts_[k + 1]) with k = (cx - min_cx_) * ny_ + (cy - min_cy_):
  // one lookup instead of a binary search per cell. Otherwise starts_ is empty.
  std::vector<uint32_t> starts_;
  long long min_cx_ = 0, min_cy_ = 0, nx_ = 0, ny_ = 0;
};

// The unit normal of the target around target[j] when its neighbours within radius_m (at
// least three, `grid` built over `target`) lie along a line: PCA's smaller eigenvalue at most
// line_ratio × the larger. nullopt otherwise (a corner, a piling, too few neighbours).
std::optional<Eigen::Vector2d> line_normal(const std::vector<Eigen::Vector2d>& target, const Grid2d& grid,
                                           size_t j, double radius_m, double line_ratio);

}  // namespace orthosonar::slam
