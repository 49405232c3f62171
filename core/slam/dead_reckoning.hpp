#pragma once
// Dead reckoning (SPEC §2): DVL body velocity rotated into W by the IMU orientation at the
// DVL stamp, integrated trapezoidally in time; z from depth (z = -depth); roll, pitch and
// yaw from the IMU (through an optional attitude filter, DrConfig), or yaw from a
// fibre-optic gyro when the source has one (gyro_heading.hpp). DVL faults (invalid, non-finite, faster than max_speed_mps) are
// rejected and counted; the last good velocity is held for at most hold_s, then the
// vehicle is assumed still and the dropout gap is reported.
//
// Feed events in stamp order (SPEC §9). A DVL reading before the first IMU reading cannot
// be rotated into W and is skipped (counted in dvl_before_imu). Not thread-safe.
#include <cstddef>
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "core/events.hpp"
#include "core/geometry.hpp"
#include "core/result.hpp"
#include "core/slam/gyro_heading.hpp"
#include "core/time.hpp"

namespace orthosonar::slam {

struct DrConfig {
  double max_speed_mps = 2.0;    // a DVL speed above this is a fault
  double hold_s = 2.0;           // hold the last good velocity this long, then assume zero
  Vec2 initial_xy_m = Vec2::Zero();  // W position of the first DR state
  // Attitude filter (addition to SPEC §2; 0 = use each IMU orientation as it comes): a
  // complementary filter that propagates roll, pitch and yaw with the gyro rates and pulls
  // them towards the IMU's orientation with this time constant. It removes the
  // orientation's per-sample noise (0.2 deg yaw on the simulator, so keyframe headings
  // scattered by +-0.3 deg and points 20 m out by 0.1 m) and follows the slow heading
  // drift with a lag of tau x drift rate. docs/SLAM.md "Attitude filter".
  double attitude_filter_tau_s = 5.0;
  double attitude_filter_max_gap_s = 0.5;  // a longer IMU gap restarts the filter
  // The filter needs gyro rates: a source whose rates are all exactly zero (no gyro output)
  // or not finite gets the orientation as is.
  // Fibre-optic gyro (docs/SLAM.md "Heading from a fibre-optic gyro"): with gyro events and
  // use_gyro, the heading is the gyro's (gyro_heading.hpp); roll and pitch stay the IMU's.
  // Without gyro events nothing changes. The noise figures set the DR odometry factors'
  // heading sigma in the pose graph (heading_sigma_rad).
  bool use_gyro = true;
  GyroHeadingConfig gyro;                    // mounting T_V_gyro and latitude_deg
  double gyro_arw_deg_per_sqrt_h = 0.012;    // angle random walk (DSP-1760 datasheet)
  double gyro_bias_dph = 0.05;               // bias (in-run stability) the heading may drift by
  // The DVL's noise figures (translation_sigma_m): white velocity noise per reading (SPEC
  // §10's 0.01 m/s) and a scale-factor error (a bottom-tracking DVL's few tenths of a per
  // cent of the distance).
  double dvl_velocity_sigma_mps = 0.01;
  double dvl_scale_sigma = 0.003;
  // Over a dropout (no good reading for longer than hold_s) DR assumes the held, then zero,
  // velocity: the vehicle's speed is unknown by about this much.
  double dvl_dropout_speed_sigma_mps = 0.5;
};

struct DrCounts {
  size_t dvl_ok = 0;
  size_t dvl_invalid = 0;     // flagged invalid by the device
  size_t dvl_nonfinite = 0;   // NaN / inf component
  size_t dvl_too_fast = 0;    // |v| > max_speed_mps
  size_t dvl_before_imu = 0;  // skipped: no orientation known yet
  size_t imu_nonfinite = 0;   // IMU readings skipped: NaN / inf orientation
  GyroCounts gyro;            // fibre-optic gyro samples used, skipped, gaps bridged
  size_t dropouts = 0;        // number of gaps longer than hold_s without a good reading
  // Each dropout: (last good DVL stamp, next good DVL stamp, or the last DVL stamp seen
  // while the dropout is still open).
  std::vector<std::pair<Time, Time>> gaps;
};

class DeadReckoning {
 public:
  explicit DeadReckoning(DrConfig config = {});

  void add(const ImuReading& r);
  void add(const DvlReading& r);
  void add(const DepthReading& r);
  void add(const GyroReading& r);

  // True once the heading comes from a fibre-optic gyro.
  bool gyro_heading() const { return config_.use_gyro && gyro_.active(); }
  // The heading's standard deviation accumulated from a to b by the gyro (angle random walk
  // and bias over b - a); nullopt when the heading is not the gyro's.
  std::optional<double> heading_sigma_rad(Time a, Time b) const;
  // The horizontal translation's standard deviation accumulated from a to b by the DVL: its
  // white velocity noise integrated over the readings (sigma_v sqrt((b - a) T), T the mean
  // reading interval), its scale error over the distance travelled and the unknown speed of
  // the dropouts inside [a, b], added in quadrature.
  // nullopt before two DVL readings or outside the DR's time span.
  std::optional<double> translation_sigma_m(Time a, Time b) const;

  // T_W_V at t: linear interpolation of translation and slerp of rotation between the
  // neighbouring DR states (one per DVL reading). An error outside [kept_from, last_time].
  Result<SE3> pose_at(Time t) const;

  // Releases the states no pose_at(t' >= t) needs: every state before the last one at or
  // before t (issue 41: a long mission's trajectory is one 136-byte state per DVL reading,
  // 3.6 MB an hour, and only the recent part is ever looked up). pose_at and
  // translation_sigma_m at stamps >= t return exactly what they returned before; earlier
  // stamps become errors. The caller (mapping::Pipeline) knows which stamps it will still ask.
  void forget_before(Time t);

  bool empty() const { return states_.empty(); }
  Time first_time() const;  // the first state's stamp, kept or not; Time() when empty
  Time last_time() const;
  Time kept_from() const;   // the oldest state still held; Time() when empty
  size_t states_kept() const { return states_.size(); }
  const DrCounts& counts() const { return counts_; }
  const DrConfig& config() const { return config_; }
  // Heap bytes of the DR trajectory (one state per DVL reading since forget_before's stamp)
  // and the recent sensor histories (core/memory.hpp).
  int64_t memory_bytes() const;

 private:
  struct State {
    Time stamp;
    SE3 T_W_V;
  };
  Quat orientation_at(Time t) const;      // the IMU's, with the gyro's heading when there is one
  Quat imu_orientation_at(Time t) const;  // IMU slerp, held at the ends
  double z_at(Time t) const;          // -depth, linear, held at the ends; 0 before any depth
                                      // (states made then are fixed by the first reading)

  DrConfig config_;
  DrCounts counts_;
  std::deque<State> states_;   // since forget_before's stamp (a deque: released from the front)
  Time first_state_;           // the first state's stamp, released or not
  Time dvl_first_;        // the first DVL reading's stamp (the interval's mean: span / count)
  size_t dvl_readings_ = 0;
  std::deque<std::pair<Time, Quat>> imu_;       // recent (filtered) IMU orientations (pruned)
  Vec3 rpy_filtered_ = Vec3::Zero();            // attitude filter state
  Time imu_last_;
  bool have_filter_ = false;
  bool rates_seen_ = false;                     // some reading had non-zero gyro rates
  GyroHeading gyro_;
  std::deque<std::pair<Time, double>> depth_;   // recent depth readings (pruned)
  Vec2 xy_ = Vec2::Zero();
  Vec3 v_W_prev_ = Vec3::Zero();   // W velocity used at the previous state
  Vec3 v_V_good_ = Vec3::Zero();   // last good body velocity
  Time last_good_;
  bool have_good_ = false;
  bool in_dropout_ = false;
};

}  // namespace orthosonar::slam
