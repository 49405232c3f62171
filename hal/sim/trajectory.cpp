#include "hal/sim/trajectory.hpp"
#include "core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace orthosonar::sim {
namespace {

double roll_at(const VehicleConfig& c, double t) {
  return c.roll_amplitude_deg * kRadPerDeg * std::sin(2.0 * std::numbers::pi * t / c.roll_period_s);
}
double pitch_at(const VehicleConfig& c, double t) {
  return c.pitch_amplitude_deg * kRadPerDeg * std::sin(2.0 * std::numbers::pi * t / c.pitch_period_s + 1.0);
}

}  // namespace

Trajectory::Trajectory(const std::vector<Waypoint>& route, double depth_m, const VehicleConfig& c, Time duration)
    : step_(Time::from_seconds(c.step_s)), duration_(duration), config_(c) {
  const double dt = step_.seconds();
  const auto steps = static_cast<size_t>(duration.ns() / step_.ns()) + 2;
  samples_.reserve(steps);
  Vec2 p = route.empty() ? Vec2::Zero() : Vec2(route[0].x_m, route[0].y_m);
  size_t target = route.size() > 1 ? 1 : 0;
  double yaw = route.size() > 1 ? std::atan2(route[1].y_m - p.y(), route[1].x_m - p.x()) : 0.0;
  const Vec2 current(c.current_x_mps, c.current_y_mps);
  const double max_rate = c.max_yaw_rate_dps * kRadPerDeg;
  for (size_t k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) * dt;
    double speed = 0.0, yaw_rate = 0.0;
    if (route.size() > 1) {
      // Advance past reached waypoints (at most one lap per step, so a degenerate route ends).
      for (size_t guard = 0; guard < route.size(); ++guard) {
        const Vec2 w(route[target].x_m, route[target].y_m);
        if ((w - p).norm() >= c.acceptance_radius_m) break;
        target = (target + 1) % route.size();
        if (target == 0) ++laps_;
      }
      const Vec2 w(route[target].x_m, route[target].y_m);
      const double err = wrap_angle(std::atan2(w.y() - p.y(), w.x() - p.x()) - yaw);
      yaw_rate = std::clamp(c.yaw_gain_per_s * err, -max_rate, max_rate);
      const double slow = std::min(1.0, std::abs(err) / (0.5 * std::numbers::pi));
      speed = c.speed_mps * (1.0 - (1.0 - c.slow_turn_factor) * slow);
    }
    VehicleState s;
    s.p_W = Vec3(p.x(), p.y(), -depth_m);
    s.yaw_rad = yaw;
    s.roll_rad = roll_at(c, t);
    s.pitch_rad = pitch_at(c, t);
    const Vec2 v = speed * Vec2(std::cos(yaw), std::sin(yaw)) + (route.size() > 1 ? current : Vec2::Zero());
    s.v_W_mps = Vec3(v.x(), v.y(), 0.0);
    const double h = 1e-3;
    s.omega_V_rps = Vec3((roll_at(c, t + h) - roll_at(c, t - h)) / (2 * h),
                         (pitch_at(c, t + h) - pitch_at(c, t - h)) / (2 * h), yaw_rate);
    samples_.push_back(s);
    if (k > 0) path_length_m_ += v.norm() * dt;
    p += v * dt;
    yaw = wrap_angle(yaw + yaw_rate * dt);
  }
}

VehicleState Trajectory::at(Time t) const {
  const int64_t ns = std::clamp<int64_t>(t.ns(), 0, static_cast<int64_t>(samples_.size() - 1) * step_.ns());
  const auto k = static_cast<size_t>(ns / step_.ns());
  const int64_t rem = ns - static_cast<int64_t>(k) * step_.ns();
  if (rem == 0 || k + 1 >= samples_.size()) {
    VehicleState s = samples_[std::min(k, samples_.size() - 1)];
    return s;
  }
  const double f = static_cast<double>(rem) / static_cast<double>(step_.ns());
  const VehicleState& a = samples_[k];
  const VehicleState& b = samples_[k + 1];
  VehicleState s;
  s.p_W = a.p_W + f * (b.p_W - a.p_W);
  s.yaw_rad = wrap_angle(a.yaw_rad + f * wrap_angle(b.yaw_rad - a.yaw_rad));
  const double ts = static_cast<double>(ns) * 1e-9;
  s.roll_rad = roll_at(config_, ts);
  s.pitch_rad = pitch_at(config_, ts);
  s.v_W_mps = a.v_W_mps + f * (b.v_W_mps - a.v_W_mps);
  s.omega_V_rps = a.omega_V_rps + f * (b.omega_V_rps - a.omega_V_rps);
  return s;
}

}  // namespace orthosonar::sim
