#include "core/slam/dead_reckoning.hpp"

#include "core/memory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace orthosonar::slam {
namespace {

// Readings older than this behind the newest are no longer needed for interpolation.
constexpr int64_t kKeepNs = 10'000'000'000;

// Drops readings older than kKeepNs before the newest, keeping one before the cutoff as an
// interpolation anchor (once 64 or more are held). A deque: one pop per reading, where a
// vector's erase at the front moved every reading kept (issue 37).
template <class V>
void prune(std::deque<std::pair<Time, V>>& series) {
  if (series.size() < 64) return;
  const Time cutoff = series.back().first - Time::from_ns(kKeepNs);
  if (series.front().first >= cutoff) return;
  while (series.size() >= 2 && series[1].first < cutoff) series.pop_front();
}

// Index i with series[i].first <= t < series[i+1].first, clamped to the ends.
template <class V>
size_t bracket(const std::deque<std::pair<Time, V>>& series, Time t) {
  auto it = std::upper_bound(series.begin(), series.end(), t,
                             [](Time a, const auto& e) { return a < e.first; });
  if (it == series.begin()) return 0;
  return static_cast<size_t>(it - series.begin()) - 1;
}

double fraction(Time a, Time b, Time t) {
  if (b <= a) return 0.0;
  return std::clamp(static_cast<double>((t - a).ns()) / static_cast<double>((b - a).ns()), 0.0, 1.0);
}

}  // namespace

DeadReckoning::DeadReckoning(DrConfig config) : config_(std::move(config)), gyro_(config_.gyro) {
  xy_ = config_.initial_xy_m;
}

void DeadReckoning::add(const ImuReading& r) {
  if (!imu_.empty() && r.stamp < imu_.back().first) return;  // out of order: ignore
  if (!r.q_W_V.coeffs().allFinite()) {  // would make every later pose (and voxel key) NaN
    ++counts_.imu_nonfinite;
    return;
  }
  const Quat q = r.q_W_V.normalized();
  if (config_.use_gyro) gyro_.add_imu_heading(r.stamp, rpy_from_rotation(q.toRotationMatrix()).z());
  const double tau = config_.attitude_filter_tau_s;
  // A device set up without gyro output reports rates of exactly zero (hal/drivers/vn100.cpp
  // leaves them so); a real gyro never does on all three axes. Until a source has shown
  // rates, and for any reading whose rates are not finite, the orientation is used as is.
  rates_seen_ = rates_seen_ || !r.angular_velocity_V.isZero(0.0);
  if (!(tau > 0.0) || !rates_seen_ || !r.angular_velocity_V.allFinite()) {
    have_filter_ = false;  // restart on the next usable reading
    imu_.emplace_back(r.stamp, q);
    prune(imu_);
    return;
  }
  const Vec3 meas = rpy_from_rotation(q.toRotationMatrix());
  const double dt = have_filter_ ? (r.stamp - imu_last_).seconds() : 0.0;
  if (!have_filter_ || dt > config_.attitude_filter_max_gap_s) {
    rpy_filtered_ = meas;  // (re)start on the measurement
  } else {
    // Propagate with the body rates (ZYX Euler kinematics), then blend towards the
    // measurement with gain dt / (tau + dt); angle differences wrapped.
    const double phi = rpy_filtered_.x(), theta = rpy_filtered_.y();
    const Vec3& w = r.angular_velocity_V;
    const double c_theta = std::max(std::cos(theta), 1e-3);
    const Vec3 rate(w.x() + std::tan(theta) * (std::sin(phi) * w.y() + std::cos(phi) * w.z()),
                    std::cos(phi) * w.y() - std::sin(phi) * w.z(),
                    (std::sin(phi) * w.y() + std::cos(phi) * w.z()) / c_theta);
    const double k = dt / (tau + dt);
    for (int i = 0; i < 3; ++i) {
      const double pred = rpy_filtered_[i] + rate[i] * dt;
      rpy_filtered_[i] = wrap_angle(pred + k * wrap_angle(meas[i] - pred));
    }
  }
  have_filter_ = true;
  imu_last_ = r.stamp;
  imu_.emplace_back(r.stamp, Quat(se3_from_xyz_rpy(0, 0, 0, rpy_filtered_.x(), rpy_filtered_.y(),
                                                   rpy_filtered_.z())
                                      .rotation()));
  prune(imu_);
}

void DeadReckoning::add(const DepthReading& r) {
  if (!std::isfinite(r.depth_m)) return;
  if (!depth_.empty() && r.stamp < depth_.back().first) return;
  if (depth_.empty()) {
    // States made before the first depth reading take it (the vehicle works at a fixed
    // depth; leaving them at z = 0 would put a metres-high step into the trajectory).
    for (State& s : states_) s.T_W_V.translation().z() = -r.depth_m;
  }
  depth_.emplace_back(r.stamp, -r.depth_m);
  prune(depth_);
}

void DeadReckoning::add(const GyroReading& r) {
  if (!config_.use_gyro) return;
  gyro_.add(r, [this](Time t) -> std::optional<Quat> {
    if (imu_.empty()) return std::nullopt;
    return imu_orientation_at(t);
  });
  counts_.gyro = gyro_.counts();
}

std::optional<double> DeadReckoning::heading_sigma_rad(Time a, Time b) const {
  if (!gyro_heading()) return std::nullopt;
  const double dt = std::abs((b - a).seconds());
  const double arw = config_.gyro_arw_deg_per_sqrt_h * std::numbers::pi / 180.0 / 60.0;  // rad/sqrt(s)
  const double bias = config_.gyro_bias_dph * std::numbers::pi / 180.0 / 3600.0;       // rad/s
  return std::sqrt(arw * arw * dt + bias * dt * bias * dt);
}

std::optional<double> DeadReckoning::translation_sigma_m(Time a, Time b) const {
  if (dvl_readings_ < 2) return std::nullopt;
  const auto pa = pose_at(a), pb = pose_at(b);
  if (!pa.ok() || !pb.ok()) return std::nullopt;
  const double period = (states_.back().stamp - dvl_first_).seconds() / static_cast<double>(dvl_readings_ - 1);
  const double dt = std::abs((b - a).seconds());
  const double d = (pb->translation() - pa->translation()).head<2>().norm();
  const double white = config_.dvl_velocity_sigma_mps * config_.dvl_velocity_sigma_mps * dt * period;
  const double scale = config_.dvl_scale_sigma * d;
  double dropout = 0.0;  // seconds of [a, b] inside dropouts
  const Time lo = std::min(a, b), hi = std::max(a, b);
  for (const auto& [from, to] : counts_.gaps) dropout += std::max(0.0, (std::min(hi, to) - std::max(lo, from)).seconds());
  const double lost = config_.dvl_dropout_speed_sigma_mps * dropout;
  return std::sqrt(white + scale * scale + lost * lost);
}

Quat DeadReckoning::orientation_at(Time t) const {
  const Quat q = imu_orientation_at(t);
  if (!gyro_heading()) return q;
  const Vec3 rpy = rpy_from_rotation(q.toRotationMatrix());
  return Quat(se3_from_xyz_rpy(0, 0, 0, rpy.x(), rpy.y(), *gyro_.yaw_at(t)).rotation());
}

Quat DeadReckoning::imu_orientation_at(Time t) const {
  const size_t i = bracket(imu_, t);
  if (i + 1 >= imu_.size() || t <= imu_[i].first) return imu_[i].second;
  return imu_[i].second.slerp(fraction(imu_[i].first, imu_[i + 1].first, t), imu_[i + 1].second);
}

double DeadReckoning::z_at(Time t) const {
  if (depth_.empty()) return 0.0;
  const size_t i = bracket(depth_, t);
  if (i + 1 >= depth_.size() || t <= depth_[i].first) return depth_[i].second;
  const double s = fraction(depth_[i].first, depth_[i + 1].first, t);
  return (1.0 - s) * depth_[i].second + s * depth_[i + 1].second;
}

void DeadReckoning::add(const DvlReading& r) {
  if (imu_.empty()) {
    ++counts_.dvl_before_imu;
    return;
  }
  if (!states_.empty() && r.stamp <= states_.back().stamp) return;  // out of order / duplicate
  if (dvl_readings_++ == 0) dvl_first_ = r.stamp;
  const Vec3& v = r.velocity_V_mps;
  bool good = false;
  if (!r.valid) {
    ++counts_.dvl_invalid;
  } else if (!v.allFinite()) {
    ++counts_.dvl_nonfinite;
  } else if (v.norm() > config_.max_speed_mps) {
    ++counts_.dvl_too_fast;
  } else {
    ++counts_.dvl_ok;
    good = true;
  }
  const Quat q = orientation_at(r.stamp);
  const Time hold = Time::from_seconds(config_.hold_s);

  if (states_.empty()) {
    // The first state starts the integration; velocity from here on.
    v_W_prev_ = good ? Vec3(q * v) : Vec3::Zero();
    if (good) {
      v_V_good_ = v;
      last_good_ = r.stamp;
      have_good_ = true;
    }
    SE3 T = SE3::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Vec3(xy_.x(), xy_.y(), z_at(r.stamp));
    states_.push_back({r.stamp, T});
    first_state_ = r.stamp;
    return;
  }

  const Time t0 = states_.back().stamp;
  // Velocity in W at this stamp: the reading, the held one (rotated by the current
  // orientation), or zero once the hold expired.
  Vec3 v_W_now = Vec3::Zero();
  const bool hold_valid = have_good_ && r.stamp - last_good_ <= hold;
  if (good) {
    v_W_now = q * v;
  } else if (hold_valid) {
    v_W_now = q * v_V_good_;
  }
  Vec2 dxy = Vec2::Zero();
  const bool hold_expires_inside = have_good_ && t0 - last_good_ < hold && r.stamp - last_good_ > hold;
  if (hold_expires_inside) {
    // Held velocity until the hold ends, then nothing moves until this reading.
    dxy = v_W_prev_.head<2>() * (last_good_ + hold - t0).seconds();
  } else if (have_good_ && t0 - last_good_ >= hold) {
    dxy = Vec2::Zero();  // still in (or leaving) a dropout: zero velocity over the interval
  } else {
    dxy = 0.5 * (v_W_prev_.head<2>() + v_W_now.head<2>()) * (r.stamp - t0).seconds();
  }
  xy_ += dxy;

  if (good) {
    if (in_dropout_) {
      counts_.gaps.back().second = r.stamp;
      in_dropout_ = false;
    } else if (have_good_ && r.stamp - last_good_ > hold) {
      // A silence (no readings at all) longer than the hold is a dropout too.
      ++counts_.dropouts;
      counts_.gaps.emplace_back(last_good_, r.stamp);
    }
    v_V_good_ = v;
    last_good_ = r.stamp;
    have_good_ = true;
  } else if (have_good_ && !in_dropout_ && r.stamp - last_good_ > hold) {
    in_dropout_ = true;
    ++counts_.dropouts;
    counts_.gaps.emplace_back(last_good_, r.stamp);
  } else if (in_dropout_) {
    counts_.gaps.back().second = r.stamp;
  }
  v_W_prev_ = v_W_now;

  SE3 T = SE3::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Vec3(xy_.x(), xy_.y(), z_at(r.stamp));
  states_.push_back({r.stamp, T});
}

Result<SE3> DeadReckoning::pose_at(Time t) const {
  if (states_.empty()) return Error{"dead reckoning: no state yet"};
  if (t < states_.front().stamp || t > states_.back().stamp) {
    return Error{"dead reckoning: stamp " + std::to_string(t.ns()) + " ns outside [" +
                 std::to_string(states_.front().stamp.ns()) + ", " +
                 std::to_string(states_.back().stamp.ns()) + "] ns" +
                 (t < states_.front().stamp && first_state_ < states_.front().stamp
                      ? " (states before " + std::to_string(states_.front().stamp.ns()) + " ns were released)"
                      : std::string())};
  }
  auto it = std::upper_bound(states_.begin(), states_.end(), t,
                             [](Time a, const State& s) { return a < s.stamp; });
  const size_t i = static_cast<size_t>(it - states_.begin()) - 1;
  if (i + 1 >= states_.size() || t == states_[i].stamp) return states_[i].T_W_V;
  return interpolate(states_[i].T_W_V, states_[i + 1].T_W_V,
                     fraction(states_[i].stamp, states_[i + 1].stamp, t));
}

void DeadReckoning::forget_before(Time t) {
  while (states_.size() >= 2 && states_[1].stamp <= t) states_.pop_front();
}

Time DeadReckoning::first_time() const { return states_.empty() ? Time() : first_state_; }
Time DeadReckoning::kept_from() const { return states_.empty() ? Time() : states_.front().stamp; }
Time DeadReckoning::last_time() const { return states_.empty() ? Time() : states_.back().stamp; }

int64_t DeadReckoning::memory_bytes() const {
  return heap_bytes(states_) + heap_bytes(imu_) + heap_bytes(depth_) + heap_bytes(counts_.gaps) + gyro_.memory_bytes();
}

}  // namespace orthosonar::slam
