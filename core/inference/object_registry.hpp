#pragma once
// Per-class reference frames (SPEC §8, paper §VI-B). Each sighting of an object is first
// expressed in its own planar sighting frame: origin at (minimum range, median bearing)
// of its pixels, x along the median bearing. The first sighting of a class fixes the
// class's reference frame and its points form the reference cloud; every later sighting
// is registered to that cloud by 2D ICP (core/slam's icp_2d) and, when it contributes 3D
// points, its registered pixels join the cloud (voxel-deduplicated and capped, so the
// cloud stays small). Not thread-safe; deterministic.
#include <cstddef>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "core/slam/icp.hpp"

namespace orthosonar::inference {

struct RegistrationConfig {
  slam::IcpConfig icp = [] {
    slam::IcpConfig c;
    c.max_iterations = 20;
    c.max_correspondence_m = 0.6;
    c.trim_fraction = 0.8;
    c.min_correspondences = 10;
    return c;
  }();
  double max_rmse_m = 0.25;          // reject a registration worse than this
  double max_translation_m = 2.0;    // ... or one that moves the object further than this
  double reference_voxel_m = 0.05;   // reference cloud deduplication
  size_t max_reference_points = 1500;
};

struct SightingFrame {
  double range_min_m = 0.0;
  double bearing_median_rad = 0.0;
};

// Origin of a sighting from its pixels' ranges and bearings (the lower median for even
// counts, so it is always one of the bearings).
SightingFrame sighting_frame(const std::vector<double>& ranges_m, const std::vector<double>& bearings_rad);
// A return at (R, θ) in the sighting frame (planar, φ = 0).
Vec2 to_sighting(const SightingFrame& frame, double range_m, double bearing_rad);

struct Registration {
  SE2 T_ref_obj;        // maps sighting-frame points into the class reference frame
  bool first_sighting = false;
  int iterations = 0;
  double rmse_m = 0.0;
};

class ClassReference {
 public:
  explicit ClassReference(const RegistrationConfig& config = {}) : config_(config) {}
  bool empty() const { return points_.empty(); }
  // Registers a sighting (points in its sighting frame). When the class has no reference
  // yet, this sighting becomes it (identity). nullopt when ICP fails or is implausible.
  std::optional<Registration> register_sighting(const std::vector<Vec2>& points_obj);
  // Adds points (reference frame) to the reference cloud.
  void add(const std::vector<Vec2>& points_ref);
  const std::vector<Vec2>& points() const { return points_; }

 private:
  RegistrationConfig config_;
  std::vector<Vec2> points_;
  std::set<std::pair<long, long>> voxels_;
};

}  // namespace orthosonar::inference
