// Heading from a fibre-optic gyro: Earth-rate removal at the latitude, the mounting, delta
// angles and rates alike, the IMU's roll and pitch in the heading rate, skipped and bridged
// samples, and dead reckoning taking its heading from the gyro (and only when there is one).
#include "core/slam/gyro_heading.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <tuple>

#include "core/slam/dead_reckoning.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int64_t kPeriodNs = 4'000'000;  // 250 Hz, as the authors configured the DSP-1760

Eigen::Matrix3d rpy_matrix(double r, double p, double y) { return se3_from_xyz_rpy(0, 0, 0, r, p, y).rotation(); }

// A vehicle at constant roll and pitch turning at yaw_rate about W's z, seen by a gyro
// mounted with R_V_G at `lat`: per sample the body rotation since the previous sample plus
// the Earth rate, in G (delta angles, or rates when `rates`).
struct Mission {
  double roll = 0.0, pitch = 0.0, yaw0 = 0.3, yaw_rate = 0.0, lat_deg = 40.706;
  Eigen::Matrix3d R_V_G = Eigen::Matrix3d::Identity();
  bool rates = false;

  double yaw(Time t) const { return yaw0 + yaw_rate * t.seconds(); }
  Quat attitude(Time t) const { return Quat(rpy_matrix(roll, pitch, yaw(t))); }
  GyroReading sample(int64_t k) const {
    const Time t = Time::from_ns(k * kPeriodNs), t0 = Time::from_ns((k - 1) * kPeriodNs);
    const Eigen::AngleAxisd turn(attitude(t0).toRotationMatrix().transpose() * attitude(t).toRotationMatrix());
    const double T = 1e-9 * kPeriodNs, lat = lat_deg * kDeg;
    Vec3 d_V = turn.angle() * turn.axis();
    d_V += attitude(t).toRotationMatrix().transpose() * Vec3(0, std::cos(lat), std::sin(lat)) * kEarthRateRadPerS * T;
    const Vec3 d_G = R_V_G.transpose() * d_V;
    GyroReading g;
    g.stamp = t;
    g.is_rate = rates;
    g.value_G = rates ? Vec3(d_G / T) : d_G;
    return g;
  }
  GyroHeading::ImuAt imu(double yaw_error = 0.0) const {
    return [this, yaw_error](Time t) -> std::optional<Quat> { return Quat(rpy_matrix(roll, pitch, yaw(t) + yaw_error)); };
  }
};

double run_heading_error(const Mission& m, const GyroHeadingConfig& cfg, double seconds, GyroHeading* out = nullptr) {
  GyroHeading h(cfg);
  const int64_t n = static_cast<int64_t>(seconds * 1e9) / kPeriodNs;
  for (int64_t k = 0; k <= n; ++k) h.add(m.sample(k), m.imu());
  const Time end = Time::from_ns(n * kPeriodNs);
  const double err = wrap_angle(*h.yaw_at(end) - m.yaw(end));
  if (out != nullptr) *out = h;
  return err;
}

}  // namespace

TEST_CASE("gyro heading removes the Earth's rotation at the configured latitude", "[unit][gyro]") {
  Mission still;  // a vehicle holding station for an hour
  GyroHeadingConfig cfg;
  cfg.latitude_deg = still.lat_deg;
  CHECK(std::abs(run_heading_error(still, cfg, 3600.0)) < 1e-6);
  // At the wrong latitude (the equator: no vertical Earth rate removed) the heading drifts by
  // the vertical Earth rate, 15.04107 sin(40.706 deg) = 9.81 deg per hour.
  GyroHeadingConfig equator = cfg;
  equator.latitude_deg = 0.0;
  const double drift_deg = run_heading_error(still, equator, 3600.0) / kDeg;
  CHECK(drift_deg == Approx(15.04107 * std::sin(40.706 * kDeg)).margin(1e-3));
}

TEST_CASE("gyro heading follows a turning, rolled and pitched vehicle, delta angles and rates agree", "[unit][gyro]") {
  Mission m;
  m.yaw_rate = 3.0 * kDeg;
  m.roll = 4.0 * kDeg;
  m.pitch = -6.0 * kDeg;
  GyroHeadingConfig cfg;
  CHECK(std::abs(run_heading_error(m, cfg, 600.0)) < 1e-6);
  m.rates = true;
  CHECK(std::abs(run_heading_error(m, cfg, 600.0)) < 1e-6);
  // The rolled vehicle's yaw rate is not the gyro's z alone: dropping the Euler kinematics
  // (roll and pitch taken as zero) would be wrong by ~(1 - cos 4 deg cos 6 deg) x 1800 deg.
  Mission level = m;
  level.roll = level.pitch = 0.0;
  CHECK(std::abs(run_heading_error(level, cfg, 600.0)) < 1e-6);
}

TEST_CASE("gyro heading rotates the gyro frame into V by the mounting", "[unit][gyro]") {
  Mission m;
  m.yaw_rate = 2.0 * kDeg;
  m.R_V_G = rpy_matrix(90.0 * kDeg, 0.0, 180.0 * kDeg);  // mounted on its side, facing aft
  GyroHeadingConfig cfg;
  cfg.T_V_gyro.linear() = m.R_V_G;
  CHECK(std::abs(run_heading_error(m, cfg, 300.0)) < 1e-6);
  GyroHeadingConfig unmounted;  // the same samples read as if G were V: wrong
  CHECK(std::abs(run_heading_error(m, unmounted, 300.0)) > 1.0 * kDeg);
}

TEST_CASE("gyro heading starts from the IMU, skips bad samples and bridges gaps with the IMU", "[unit][gyro]") {
  Mission m;
  m.yaw_rate = 1.0 * kDeg;
  GyroHeading h;
  // Before any attitude: counted, not used.
  h.add(m.sample(0), [](Time) -> std::optional<Quat> { return std::nullopt; });
  CHECK(h.counts().before_imu == 1);
  CHECK_FALSE(h.active());
  // The start takes the IMU's heading, its error included (a FOG cannot find north).
  const double imu_error = 0.5 * kDeg;
  h.add(m.sample(1), m.imu(imu_error));
  REQUIRE(h.active());
  CHECK(*h.yaw_at(Time::from_ns(kPeriodNs)) == Approx(m.yaw(Time::from_ns(kPeriodNs)) + imu_error).margin(1e-12));
  for (int64_t k = 2; k < 1000; ++k) {
    GyroReading g = m.sample(k);
    if (k == 100) g.valid = false;                  // the device says bad: skipped, counted
    if (k == 200) g.value_G.x() = std::nan("");     // not finite: skipped, counted
    if (k >= 300 && k < 400) continue;              // 100 samples lost
    h.add(g, m.imu(imu_error));
  }
  CHECK(h.counts().invalid == 1);
  CHECK(h.counts().nonfinite == 1);
  CHECK(h.counts().gaps == 3);  // after the invalid, the non-finite and the lost samples
  CHECK(h.counts().used == 999 - 2 - 100);  // samples 1..999
  // The gaps were bridged with the IMU's heading change (exact here), so nothing is lost.
  const Time end = Time::from_ns(999 * kPeriodNs);
  CHECK(*h.yaw_at(end) == Approx(wrap_angle(m.yaw(end) + imu_error)).margin(1e-9));
  // Between samples: linear.
  const Time mid = Time::from_ns(500 * kPeriodNs + kPeriodNs / 2);
  CHECK(*h.yaw_at(mid) == Approx(m.yaw(mid) + imu_error).margin(1e-9));
}

TEST_CASE("dead reckoning takes its heading from the gyro when there is one, and only then", "[unit][gyro]") {
  // The IMU's heading drifts 0.004 deg/s (the simulator's ahrs profile); the gyro does not.
  Mission m;
  m.yaw_rate = 0.5 * kDeg;
  const double drift = 0.004 * kDeg;
  auto feed = [&](DeadReckoning& dr, bool with_gyro) {
    for (int64_t k = 0; k * kPeriodNs <= 600'000'000'000; ++k) {
      const Time t = Time::from_ns(k * kPeriodNs);
      if (k % 25 == 0)  // 10 Hz IMU
        dr.add(ImuReading{t, Quat(rpy_matrix(0, 0, m.yaw(t) + drift * t.seconds())), Vec3(0, 0, m.yaw_rate), Vec3::Zero()});
      if (with_gyro && k > 0) dr.add(m.sample(k));
      if (k % 50 == 0) {
        dr.add(DepthReading{t, 3.0});
        dr.add(DvlReading{t, Vec3(0.5, 0, 0), true, 5.0});
      }
    }
  };
  DrConfig cfg;
  DeadReckoning ahrs(cfg), fog(cfg);
  feed(ahrs, false);
  feed(fog, true);
  const Time t = Time::from_seconds(600.0);
  auto yaw_error_deg = [&](const DeadReckoning& dr) {
    return wrap_angle(rpy_from_rotation(dr.pose_at(t)->rotation()).z() - m.yaw(t)) / kDeg;
  };
  CHECK(std::abs(yaw_error_deg(ahrs)) > 2.0);   // 2.4 deg of drift (less the filter's lag)
  CHECK(std::abs(yaw_error_deg(fog)) < 0.01);
  CHECK_FALSE(ahrs.gyro_heading());
  CHECK(fog.gyro_heading());
  CHECK_FALSE(ahrs.heading_sigma_rad(Time(), t).has_value());
  // ARW 0.012 deg/sqrt(h) over 600 s and 0.05 deg/h of bias over it.
  const double expect = std::hypot(0.012 * std::sqrt(600.0 / 3600.0), 0.05 * 600.0 / 3600.0) * kDeg;
  CHECK(*fog.heading_sigma_rad(Time(), t) == Approx(expect).epsilon(1e-12));
  CHECK(fog.counts().gyro.used > 100000);
  // use_gyro: false ignores it.
  cfg.use_gyro = false;
  DeadReckoning off(cfg);
  feed(off, true);
  CHECK(std::abs(yaw_error_deg(off) - yaw_error_deg(ahrs)) < 1e-12);
  CHECK(off.counts().gyro.used == 0);
}

TEST_CASE("gyro heading aligns its start on the mean IMU heading of the first align_s seconds", "[unit][gyro]") {
  // A turning vehicle whose IMU heading carries 0.2 deg of white noise per 100 Hz sample
  // (the simulator's VN-100). Started from one IMU sample, the whole mission keeps that
  // sample's error; aligned over the first second, the error of a 100-sample mean remains.
  Mission m;
  m.yaw_rate = 2.0 * kDeg;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> white(0.0, 0.2 * kDeg);
  auto run = [&](double align_s, double first_error) {
    GyroHeadingConfig cfg;
    cfg.align_s = align_s;
    GyroHeading h(cfg);
    const int64_t n = 60'000'000'000 / kPeriodNs;  // 60 s
    int64_t next_imu = 0;                            // ns
    double at_2s = 0.0;
    for (int64_t k = 0; k <= n; ++k) {
      const Time t = Time::from_ns(k * kPeriodNs);
      for (; next_imu <= t.ns(); next_imu += 10'000'000) {
        const Time ti = Time::from_ns(next_imu);
        h.add_imu_heading(ti, m.yaw(ti) + (next_imu == 0 ? first_error : white(rng)));
      }
      h.add(m.sample(k), m.imu(first_error));
      if (t.ns() == 2'000'000'000) at_2s = wrap_angle(*h.yaw_at(t) - m.yaw(t));
    }
    const Time end = Time::from_ns(n * kPeriodNs);
    return std::tuple{wrap_angle(*h.yaw_at(end) - m.yaw(end)), at_2s, h.counts().aligned};
  };
  const double first = 0.4 * kDeg;  // an unlucky first sample: two sigma
  const auto [unaligned, unaligned_2s, n0] = run(0.0, first);
  CHECK(n0 == 0);
  CHECK(unaligned == Approx(first).margin(1e-6));
  CHECK(unaligned_2s == Approx(first).margin(1e-6));
  // The IMU headings of 10 ms ... 1 s (the one at 0 s comes before any gyro sample): 100.
  const auto [aligned, aligned_2s, n1] = run(1.0, first);
  CHECK(n1 == 100);
  // The start's 0.4 deg is gone; 0.2 deg / sqrt(100) = 0.02 deg is left: within 3 sigma.
  CHECK(std::abs(aligned) < 0.06 * kDeg);
  // After the window the offset is frozen: 2 s and 60 s have the same error.
  CHECK(aligned_2s == Approx(aligned).margin(1e-6));
}
