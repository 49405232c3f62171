#pragma once
// A synthetic planar world with a known answer, for SLAM tests and benchmarks: walls and
// round pilings sampled as points, a looping route, and sonar scans taken from any pose
// (range and field-of-view limited, Gaussian range noise). Deterministic from a seed.
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace orthosonar::slam {

struct SyntheticScanConfig {
  double range_m = 30.0;
  double fov_deg = 130.0;
  double sonar_x_m = 0.35;
  double noise_m = 0.03;
  // A surface echoes over a few range bins, so detections form a band this deep behind it.
  double echo_depth_m = 0.6;
  int echo_samples = 3;
};

struct SyntheticWorld {
  std::vector<Vec2> points_W;  // structure surfaces, ~0.1 m spacing
};

// A basin: a rectangular quay wall (with a corrugated side) of size_x by size_y around the
// origin and a field of pilings inside.
SyntheticWorld make_basin_world(uint64_t seed, double size_x_m = 70.0, double size_y_m = 50.0);

// Keyframe poses on `laps` laps of a rounded rectangle (half extents hx, hy), spaced by step_m.
std::vector<SE2> loop_route(double hx_m, double hy_m, double step_m, int laps);

// Points seen by a sonar at T_W_V, in V (x, y), with noise from the seed/index stream.
std::vector<Vec2> synthetic_scan_V(const SyntheticWorld& world, const SE2& T_W_V,
                                   const SyntheticScanConfig& config, uint64_t seed, uint64_t index);

// Dead reckoning along `truth`: each relative step with a yaw error that follows a bias
// random walk (rad per step, sigma rad per step) plus translation noise.
std::vector<SE2> drifting_odometry(const std::vector<SE2>& truth, double yaw_bias_rad,
                                   double yaw_walk_rad, double xy_noise_m, uint64_t seed);

}  // namespace orthosonar::slam
