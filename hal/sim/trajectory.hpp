#pragma once
// The vehicle's ground-truth motion: waypoint following at fixed depth with a bounded yaw
// rate, a small roll/pitch sway and a water current. Integrated once at a fixed step and
// interpolated (linear translation, slerp rotation) at any stamp.
#include <vector>

#include "core/geometry.hpp"
#include "core/time.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::sim {

struct VehicleState {
  Vec3 p_W = Vec3::Zero();
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  Vec3 v_W_mps = Vec3::Zero();      // velocity over ground in W
  Vec3 omega_V_rps = Vec3::Zero();  // body rates
  SE3 T_W_V() const { return se3_from_xyz_rpy(p_W.x(), p_W.y(), p_W.z(), roll_rad, pitch_rad, yaw_rad); }
};

class Trajectory {
 public:
  // Follows route cyclically from its first waypoint, heading towards the second, from t = 0
  // to duration (plus one step). An empty route holds position.
  Trajectory(const std::vector<Waypoint>& route, double depth_m, const VehicleConfig& config,
             Time duration);
  // State at t, clamped to the simulated span.
  VehicleState at(Time t) const;
  Time duration() const { return duration_; }
  double path_length_m() const { return path_length_m_; }
  int laps_started() const { return laps_; }

 private:
  std::vector<VehicleState> samples_;
  Time step_;
  Time duration_;
  VehicleConfig config_;
  double path_length_m_ = 0.0;
  int laps_ = 0;
};

}  // namespace orthosonar::sim
