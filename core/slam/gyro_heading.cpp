#include "core/slam/gyro_heading.hpp"

#include "core/memory.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace orthosonar::slam {
namespace {

constexpr int64_t kGyroKeepNs = 10'000'000'000;  // older samples are no longer interpolated

double yaw_of(const Quat& q) { return rpy_from_rotation(q.toRotationMatrix()).z(); }

}  // namespace

GyroHeading::GyroHeading(GyroHeadingConfig config) : config_(std::move(config)) {
  R_V_G_ = config_.T_V_gyro.rotation();
  const double lat = config_.latitude_deg * std::numbers::pi / 180.0;
  earth_W_ = Vec3(0.0, std::cos(lat), std::sin(lat)) * kEarthRateRadPerS;
}

void GyroHeading::add(const GyroReading& r, const ImuAt& imu_at) {
  if (!r.valid) {
    ++counts_.invalid;
    return;
  }
  if (!r.value_G.allFinite()) {
    ++counts_.nonfinite;
    return;
  }
  if (!yaw_.empty() && r.stamp <= last_) return;  // out of order or repeated: ignore
  const std::optional<Quat> q_imu = imu_at(r.stamp);
  if (!q_imu) {
    ++counts_.before_imu;
    return;
  }
  const Vec3 rpy = rpy_from_rotation(q_imu->toRotationMatrix());
  if (yaw_.empty()) {
    // The first sample's increment covers time before any attitude: start from the IMU.
    yaw_.emplace_back(r.stamp, rpy.z());
    first_ = last_ = r.stamp;
    ++counts_.used;
    return;
  }
  const Time dt = r.stamp - last_;
  if (period_ == Time() || dt < period_) period_ = dt;
  // Delta angles cover one sample period; rates are taken over the whole interval unless
  // samples are missing, then over one period too.
  const bool gap = dt.ns() > period_.ns() + period_.ns() / 2;
  const Time covered = gap ? period_ : dt;
  const double T = covered.seconds();
  Vec3 d_V = R_V_G_ * (r.is_rate ? Vec3(r.value_G * T) : r.value_G);
  const double prev = yaw_.back().second;  // integrated, without the alignment offset
  const Eigen::Matrix3d R_W_V = se3_from_xyz_rpy(0, 0, 0, rpy.x(), rpy.y(), prev + offset_).rotation();
  d_V -= R_W_V.transpose() * earth_W_ * T;
  const double phi = rpy.x(), c_theta = std::max(std::cos(rpy.y()), 1e-3);
  double d_yaw = (std::sin(phi) * d_V.y() + std::cos(phi) * d_V.z()) / c_theta;
  if (gap) {
    ++counts_.gaps;
    const Time gap_end = r.stamp - covered;
    const std::optional<Quat> a = imu_at(last_), b = imu_at(gap_end);
    if (a && b) d_yaw += wrap_angle(yaw_of(*b) - yaw_of(*a));
  }
  yaw_.emplace_back(r.stamp, prev + d_yaw);
  last_ = r.stamp;
  ++counts_.used;
  // IMU headings between the previous sample and this one: compare with the integrated
  // heading interpolated at their stamps.
  size_t done = 0;
  for (const auto& [t, imu_yaw] : pending_) {
    if (t > r.stamp) break;
    const double s = static_cast<double>((t - (r.stamp - dt)).ns()) / static_cast<double>(dt.ns());
    align(imu_yaw - (prev + s * d_yaw));
    ++done;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(done));
  if (yaw_.size() >= 64) {
    // Keep one sample before the cutoff as an interpolation anchor; stamps increase, so
    // popping from the front is the whole prune (a vector's front erase moved 2,500
    // samples per gyro reading at 250 Hz).
    const Time cutoff = yaw_.back().first - Time::from_ns(kGyroKeepNs);
    while (yaw_.size() >= 2 && yaw_[1].first < cutoff) yaw_.pop_front();
  }
}

void GyroHeading::add_imu_heading(Time stamp, double yaw) {
  if (yaw_.empty() || !std::isfinite(yaw) || stamp < last_) return;
  if ((stamp - first_).seconds() > config_.align_s) return;
  if (stamp == last_) {  // at a sample: no interpolation needed
    align(yaw - yaw_.back().second);
    return;
  }
  pending_.emplace_back(stamp, yaw);
}

void GyroHeading::align(double imu_minus_integrated) {
  align_sum_ += wrap_angle(imu_minus_integrated);
  ++counts_.aligned;
  offset_ = align_sum_ / static_cast<double>(counts_.aligned);
}

std::optional<double> GyroHeading::yaw_at(Time t) const {
  if (yaw_.empty()) return std::nullopt;
  if (t <= yaw_.front().first) return wrap_angle(yaw_.front().second + offset_);
  if (t >= yaw_.back().first) return wrap_angle(yaw_.back().second + offset_);
  auto it = std::upper_bound(yaw_.begin(), yaw_.end(), t, [](Time a, const auto& e) { return a < e.first; });
  const auto& b = *it;
  const auto& a = *(it - 1);
  const double s = static_cast<double>((t - a.first).ns()) / static_cast<double>((b.first - a.first).ns());
  return wrap_angle(a.second + s * (b.second - a.second) + offset_);
}

int64_t GyroHeading::memory_bytes() const { return heap_bytes(yaw_) + heap_bytes(pending_); }

}  // namespace orthosonar::slam
