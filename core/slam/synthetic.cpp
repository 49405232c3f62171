#include "core/slam/synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/random.hpp"

namespace orthosonar::slam {

SyntheticWorld make_basin_world(uint64_t seed, double size_x_m, double size_y_m) {
  SyntheticWorld w;
  Rng rng(derive_seed(seed, 1));
  const double hx = 0.5 * size_x_m, hy = 0.5 * size_y_m, step = 0.1;
  for (double x = -hx; x <= hx; x += step) {
    // North wall corrugated (a sine profile), south wall straight.
    w.points_W.emplace_back(x, hy + 0.4 * std::sin(x * 1.3));
    w.points_W.emplace_back(x, -hy - 0.5 * std::fmod(x + hx, 5.0) / 5.0);  // sawtooth quay
  }
  for (double y = -hy; y <= hy; y += step) {
    w.points_W.emplace_back(-hx, y);
    w.points_W.emplace_back(hx + 0.3 * (std::fmod(std::abs(y), 4.0) < 2.0 ? 1.0 : 0.0), y);
  }
  // Pilings: circles of radius 0.3-0.6 m at random places away from the route band.
  for (int i = 0; i < 60; ++i) {
    const double cx = rng.uniform(-hx + 3.0, hx - 3.0), cy = rng.uniform(-hy + 3.0, hy - 3.0);
    const double r = rng.uniform(0.3, 0.6);
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * std::numbers::pi * k / 24.0;
      w.points_W.emplace_back(cx + r * std::cos(a), cy + r * std::sin(a));
    }
  }
  return w;
}

std::vector<SE2> loop_route(double hx_m, double hy_m, double step_m, int laps) {
  // Rectangle with rounded corners (radius 3 m), traversed counter-clockwise.
  const double rc = 3.0;
  const double sx = 2.0 * (hx_m - rc), sy = 2.0 * (hy_m - rc), arc = 0.5 * std::numbers::pi * rc;
  const double perimeter = 2.0 * (sx + sy) + 4.0 * arc;
  std::vector<SE2> out;
  const int n = static_cast<int>(std::floor(laps * perimeter / step_m));
  for (int i = 0; i <= n; ++i) {
    double s = std::fmod(i * step_m, perimeter);
    const double segs[8] = {sx, arc, sy, arc, sx, arc, sy, arc};
    // Start at the bottom edge going +x.
    double x = -hx_m + rc, y = -hy_m, th = 0.0;
    for (int k = 0; k < 8; ++k) {
      if (s <= segs[k] || k == 7) {
        if (k % 2 == 0) {
          x += std::cos(th) * s;
          y += std::sin(th) * s;
        } else {
          const double a = s / rc;
          const double cx = x - std::sin(th) * rc, cy = y + std::cos(th) * rc;
          x = cx + std::sin(th + a) * rc;
          y = cy - std::cos(th + a) * rc;
          th += a;
        }
        break;
      }
      s -= segs[k];
      if (k % 2 == 0) {
        x += std::cos(th) * segs[k];
        y += std::sin(th) * segs[k];
      } else {
        const double cx = x - std::sin(th) * rc, cy = y + std::cos(th) * rc;
        th += 0.5 * std::numbers::pi;
        x = cx + std::sin(th) * rc;
        y = cy - std::cos(th) * rc;
      }
    }
    out.push_back({x, y, wrap_angle(th)});
  }
  return out;
}

std::vector<Vec2> synthetic_scan_V(const SyntheticWorld& world, const SE2& T_W_V,
                                   const SyntheticScanConfig& config, uint64_t seed, uint64_t index) {
  Rng rng(derive_seed(seed, 2, index));
  const SE2 T_V_W = T_W_V.inverse();
  const double half = 0.5 * config.fov_deg * std::numbers::pi / 180.0;
  std::vector<Vec2> out;
  for (const Vec2& p : world.points_W) {
    const Vec2 q = T_V_W * p;
    const Vec2 s = q - Vec2(config.sonar_x_m, 0.0);
    const double r = s.norm();
    if (r > config.range_m || r < 1.0 || std::abs(std::atan2(s.y(), s.x())) > half) continue;
    for (int k = 0; k < config.echo_samples; ++k) {
      // Uniform within the echo band (no regular spacing that ICP could alias onto).
      const double depth = k == 0 ? 0.0 : config.echo_depth_m * rng.uniform();
      out.push_back(Vec2(config.sonar_x_m, 0.0) + s * ((r + depth + config.noise_m * rng.normal()) / r));
    }
  }
  return out;
}

std::vector<SE2> drifting_odometry(const std::vector<SE2>& truth, double yaw_bias_rad,
                                   double yaw_walk_rad, double xy_noise_m, uint64_t seed) {
  Rng rng(derive_seed(seed, 3));
  std::vector<SE2> out;
  if (truth.empty()) return out;
  out.push_back(truth.front());
  double bias = yaw_bias_rad;
  for (size_t i = 1; i < truth.size(); ++i) {
    SE2 d = truth[i - 1].inverse() * truth[i];
    bias += yaw_walk_rad * rng.normal();
    d.theta = wrap_angle(d.theta + bias);
    d.x += xy_noise_m * rng.normal();
    d.y += xy_noise_m * rng.normal();
    out.push_back(out.back() * d);
  }
  return out;
}

}  // namespace orthosonar::slam
