#pragma once
// Heading from a fibre-optic gyro (the paper's KVH DSP-1760; the authors' `gyro` node and
// their dead reckoning's `use_gyro`): the gyro's delta angles (or rates) rotated from its
// frame G into V by the mounting, the Earth's rotation at the latitude of operation removed
// (W is east, north, up: Earth rate Ω (0, cos lat, sin lat), seen in V through the current
// attitude), and the body rotation turned into a heading change with the IMU's roll and
// pitch (ZYX Euler kinematics: dψ = (sin φ dθy + cos φ dθz) / cos θ). A FOG holds heading
// to well under 0.1° per hour where the AHRS drifts degrees, but cannot find north here:
// the absolute heading is the IMU's, aligned as the mean offset between the IMU's heading
// and the integrated one over the first align_s seconds (one IMU sample's noise would stay
// in every heading of the mission), then held (docs/SLAM.md "Heading from a fibre-optic
// gyro").
//
// Samples must come in stamp order (SPEC §9). An invalid sample (device status) or a
// non-finite one is skipped and counted; the rotation of a gap the gyro did not cover
// (lost or skipped samples: more than half a sample period missing) is taken from the
// IMU's heading change over it and counted. Not thread-safe.
#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/time.hpp"

namespace orthosonar::slam {

// The Earth's rotation rate, 15.04107 deg per hour (one turn per sidereal day), in rad/s.
inline constexpr double kEarthRateRadPerS = 15.04107 / 3600.0 * 3.14159265358979323846 / 180.0;

struct GyroHeadingConfig {
  SE3 T_V_gyro = SE3::Identity();  // the gyro's mounting; its rotation R_V_G is used
  double latitude_deg = 40.706;    // where the vehicle works (the authors' default)
  // Start-heading alignment window (s): the heading offset is the mean of (IMU heading -
  // integrated heading) over the samples of the first align_s seconds, updated with each
  // one and frozen after. White AHRS noise s_w per sample at rate f averages to
  // s_w / sqrt(f T) while the AHRS's own error walks ~ q sqrt(T / 3): the simulator's VN-100
  // (0.2°, 100 Hz, 0.05°/√s) is best near 0.7 s. 0: the IMU's heading at the first sample.
  double align_s = 1.0;
};

struct GyroCounts {
  size_t used = 0;         // samples integrated
  size_t invalid = 0;      // flagged bad by the device
  size_t nonfinite = 0;    // NaN / inf component
  size_t before_imu = 0;   // no attitude known yet
  size_t gaps = 0;         // intervals the gyro did not cover, bridged with the IMU
  size_t aligned = 0;      // IMU headings that went into the start alignment
  friend bool operator==(const GyroCounts&, const GyroCounts&) = default;
};

class GyroHeading {
 public:
  explicit GyroHeading(GyroHeadingConfig config = {});

  // `imu_at(t)`: the IMU's orientation of V in W at t (held at its ends); nullopt when no
  // IMU reading has come yet.
  using ImuAt = std::function<std::optional<Quat>(Time)>;
  void add(const GyroReading& r, const ImuAt& imu_at);
  // The IMU's measured heading (raw, not filtered) for the start alignment; readings before
  // the first gyro sample or after the window are not used. In stamp order with add().
  void add_imu_heading(Time stamp, double yaw);

  bool active() const { return !yaw_.empty(); }
  // The integrated heading at t (rad, wrapped to (-pi, pi]): linear between samples, held
  // at the ends; nullopt before the first sample.
  std::optional<double> yaw_at(Time t) const;
  const GyroCounts& counts() const { return counts_; }
  int64_t memory_bytes() const;  // the recent heading history (core/memory.hpp)

 private:
  GyroHeadingConfig config_;
  Eigen::Matrix3d R_V_G_;
  Vec3 earth_W_;
  GyroCounts counts_;
  std::deque<std::pair<Time, double>> yaw_;   // (stamp, unwrapped heading), recent (pruned)
  Time first_;                                // the first sample integrated
  double align_sum_ = 0.0;                    // sum of (IMU - integrated) over the window
  std::vector<std::pair<Time, double>> pending_;  // IMU headings past the last gyro sample
  double offset_ = 0.0;                       // added to every integrated heading
  void align(double imu_minus_integrated);    // one IMU heading into the mean offset
  Time last_;                                 // the last sample integrated or started from
  Time period_;                               // the shortest interval seen: the sample period
};

}  // namespace orthosonar::slam
