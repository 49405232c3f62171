#pragma once
// 2D point-to-point ICP with trimming (SPEC §5), deterministic: nearest neighbours from a
// sorted uniform grid, correspondences trimmed by distance with index tie-breaks.
#include <cstddef>
#include <vector>

#include "core/geometry.hpp"

namespace orthosonar::slam {

struct IcpConfig {
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
};

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

// Nearest-neighbour index over 2D points within a fixed radius (grid of radius-sized cells,
// stored sorted; no hashing). Ties between equidistant points go to the lower index.
class Grid2d {
 public:
  Grid2d(const std::vector<Eigen::Vector2d>& points, double cell_m);
  // Index of the nearest point within max_dist, or -1.
  long nearest(const Eigen::Vector2d& q, double max_dist, double* dist2 = nullptr) const;
  // Number of points within radius of q (q itself counts if it is one of the points).
  size_t count_within(const Eigen::Vector2d& q, double radius) const;

 private:
  struct Entry {
    long long cx, cy;
    long index;
  };
  template <class F>
  void for_cell(long long cx, long long cy, F&& f) const;
  const std::vector<Eigen::Vector2d>* points_;
  double cell_m_;
  std::vector<Entry> entries_;  // sorted by (cx, cy, index)
};

}  // namespace orthosonar::slam
