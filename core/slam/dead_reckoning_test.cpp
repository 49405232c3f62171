#include "core/slam/dead_reckoning.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

using namespace orthosonar;
using namespace orthosonar::slam;

namespace {

Quat yaw_quat(double yaw) { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }

// Feeds IMU at 100 Hz (orientation yaw(t) and matching gyro rates), DVL and depth at 5 Hz
// for [0, duration] with the given body velocity; `dvl` may alter each DVL reading (faults, outages: return false to drop).
template <class YawFn, class DvlFn>
DeadReckoning run(double duration_s, YawFn yaw, const Vec3& v_V, DvlFn dvl, DrConfig cfg = {}) {
  DeadReckoning dr(cfg);
  const int64_t imu_ns = 10'000'000, dvl_every = 20;
  for (int64_t k = 0; k * imu_ns <= static_cast<int64_t>(duration_s * 1e9); ++k) {
    const Time t = Time::from_ns(k * imu_ns);
    // Body rates consistent with yaw(t) (central difference), as a gyro would report.
    const double ts = t.seconds(), h = 1e-4;
    const Vec3 rate(0.0, 0.0, (yaw(ts + h) - yaw(ts - h)) / (2.0 * h));
    dr.add(ImuReading{t, yaw_quat(yaw(ts)), rate, Vec3::Zero()});
    if (k % dvl_every == 0) {
      dr.add(DepthReading{t, 3.0});
      DvlReading r{t, v_V, true, 5.0};
      if (dvl(r)) dr.add(r);
    }
  }
  return dr;
}

}  // namespace

TEST_CASE("DR integrates constant velocity along a fixed heading", "[unit]") {
  const double yaw = 30.0 * std::numbers::pi / 180.0;
  const auto dr = run(10.0, [&](double) { return yaw; }, Vec3(1.0, 0.0, 0.0), [](DvlReading&) { return true; });
  const auto p = dr.pose_at(Time::from_seconds(5.0));
  REQUIRE(p.ok());
  CHECK(p->translation().x() == Approx(5.0 * std::cos(yaw)).margin(1e-9));
  CHECK(p->translation().y() == Approx(5.0 * std::sin(yaw)).margin(1e-9));
  CHECK(p->translation().z() == Approx(-3.0));
  CHECK(yaw_of(Quat(p->rotation())) == Approx(yaw));
  // Interpolated between DVL states (5 Hz): linear in translation.
  const auto mid = dr.pose_at(Time::from_ms(5100));
  REQUIRE(mid.ok());
  CHECK(mid->translation().x() == Approx(5.1 * std::cos(yaw)).margin(1e-9));
  CHECK(dr.counts().dvl_ok == 51);
}

TEST_CASE("DR follows a constant-rate turn within a centimetre", "[unit]") {
  const double w = 0.1, v = 0.5;  // rad/s, m/s: a circle of radius 5 m
  const auto dr = run(30.0, [&](double t) { return w * t; }, Vec3(v, 0.0, 0.0), [](DvlReading&) { return true; });
  for (double t : {10.0, 20.0, 30.0}) {
    const auto p = dr.pose_at(Time::from_seconds(t));
    REQUIRE(p.ok());
    CHECK(p->translation().x() == Approx(v / w * std::sin(w * t)).margin(0.01));
    CHECK(p->translation().y() == Approx(v / w * (1.0 - std::cos(w * t))).margin(0.01));
  }
}

TEST_CASE("DR pose_at refuses stamps outside the known span", "[unit]") {
  const auto dr = run(2.0, [](double) { return 0.0; }, Vec3(0.5, 0, 0), [](DvlReading&) { return true; });
  CHECK(dr.pose_at(Time::from_ms(0)).ok());
  CHECK(dr.pose_at(Time::from_ms(2000)).ok());
  CHECK_FALSE(dr.pose_at(Time::from_ms(2001)).ok());
  CHECK_FALSE(dr.pose_at(Time::from_ms(-1)).ok());
  CHECK_FALSE(DeadReckoning().pose_at(Time()).ok());
}

TEST_CASE("DR counts DVL faults and holds the last good velocity through them", "[unit]") {
  int n = 0;
  const auto dr = run(10.0, [](double) { return 0.0; }, Vec3(1.0, 0.0, 0.0), [&](DvlReading& r) {
    ++n;
    if (n % 10 == 3) r.valid = false;
    if (n % 10 == 5) r.velocity_V_mps.x() = std::numeric_limits<double>::quiet_NaN();
    if (n % 10 == 7) r.velocity_V_mps.x() = 2.5;
    return true;
  });
  CHECK(dr.counts().dvl_invalid == 5);
  CHECK(dr.counts().dvl_nonfinite == 5);
  CHECK(dr.counts().dvl_too_fast == 5);
  CHECK(dr.counts().dvl_ok == 36);
  CHECK(dr.counts().dropouts == 0);
  // Single faults are bridged by the held velocity: position is exact.
  CHECK(dr.pose_at(Time::from_s(10))->translation().x() == Approx(10.0).margin(1e-9));
}

TEST_CASE("DR bridges a 20 s DVL outage with a bounded hold and reports the gap", "[unit]") {
  // No DVL readings at all between 10 s and 30 s.
  const auto dr = run(40.0, [](double) { return 0.0; }, Vec3(0.5, 0.0, 0.0), [](DvlReading& r) {
    return r.stamp <= Time::from_s(10) || r.stamp > Time::from_s(30);
  });
  REQUIRE(dr.counts().dropouts == 1);
  CHECK(dr.counts().gaps[0].first == Time::from_s(10));
  CHECK(dr.counts().gaps[0].second == Time::from_ms(30200));
  // 10 s moving, 2 s held, then still until 30.2 s, then 9.8 s moving.
  CHECK(dr.pose_at(Time::from_s(40))->translation().x() == Approx(0.5 * (10.0 + 2.0 + 9.8)).margin(1e-9));
}

TEST_CASE("DR reports a dropout of invalid readings and closes it at the next good one", "[unit]") {
  const auto dr = run(20.0, [](double) { return 0.0; }, Vec3(0.5, 0.0, 0.0), [](DvlReading& r) {
    if (r.stamp > Time::from_s(5) && r.stamp < Time::from_s(10)) r.valid = false;
    return true;
  });
  REQUIRE(dr.counts().dropouts == 1);
  CHECK(dr.counts().gaps[0].first == Time::from_s(5));
  CHECK(dr.counts().gaps[0].second == Time::from_s(10));
  CHECK(dr.counts().dvl_invalid == 24);
  // Moving 5 s, held for 2 s (trapezoid ends at the last held state), zero, moving 10 s.
  const double x = dr.pose_at(Time::from_s(20))->translation().x();
  CHECK(x == Approx(0.5 * (5.0 + 2.0 + 10.0)).margin(1e-9));
}

namespace {

// Erratic but bounded values in [-1, 1], a function of the sample index only.
double jitter(int64_t k, uint64_t salt) {
  return std::sin(static_cast<double>((static_cast<uint64_t>(k) * 7919u + salt) % 1000u));
}

// IMU at 100 Hz with orientation yaw_meas(k) and a gyro reporting z rate gyro_z(k), DVL at
// 5 Hz, for n samples.
template <class Meas, class Gyro>
DeadReckoning run_imu(int64_t n, Meas yaw_meas, Gyro gyro_z, DrConfig cfg = {}) {
  DeadReckoning dr(cfg);
  for (int64_t k = 0; k <= n; ++k) {
    const Time t = Time::from_ns(k * 10'000'000);
    dr.add(ImuReading{t, yaw_quat(yaw_meas(k)), Vec3(0.0, 0.0, gyro_z(k)), Vec3::Zero()});
    if (k % 20 == 0) dr.add(DvlReading{t, Vec3(0.5, 0, 0), true, 5.0});
  }
  return dr;
}

double dr_yaw(const DeadReckoning& dr, Time t) {
  const auto p = dr.pose_at(t);
  REQUIRE(p.ok());
  return yaw_of(Quat(p->rotation()));
}

}  // namespace

TEST_CASE("the attitude filter removes per-sample heading noise", "[unit]") {
  // A fixed heading of 0.3 rad seen through 0.2 deg of noise per sample; the gyro reports
  // 0.05 deg/s of noise around zero.
  const double deg = std::numbers::pi / 180.0;
  auto meas = [&](int64_t k) { return 0.3 + 0.2 * deg * jitter(k, 0); };
  auto gyro = [&](int64_t k) { return 0.05 * deg * jitter(k, 500); };
  auto worst_error_deg = [&](const DeadReckoning& dr) {
    double worst = 0.0;
    for (int k = 100; k <= 150; ++k) worst = std::max(worst, std::abs(dr_yaw(dr, Time::from_ms(200 * k)) - 0.3));
    return worst / deg;
  };
  DrConfig raw;
  raw.attitude_filter_tau_s = 0.0;  // SPEC §2 as written: each orientation as it comes
  CHECK(worst_error_deg(run_imu(3000, meas, gyro, raw)) > 0.1);
  CHECK(worst_error_deg(run_imu(3000, meas, gyro)) < 0.03);
}

TEST_CASE("the attitude filter follows a slow heading drift with a lag of tau x rate", "[unit]") {
  // The orientation drifts at 0.01 rad/s while the gyro sees no rotation (a drifting
  // heading reference): the filter follows the reference, lagging by about tau x rate.
  const double deg = std::numbers::pi / 180.0;
  DrConfig cfg;
  cfg.attitude_filter_tau_s = 5.0;
  const auto dr = run_imu(
      6000, [](int64_t k) { return 0.01 * 0.01 * static_cast<double>(k); },
      [&](int64_t k) { return 0.05 * deg * jitter(k, 500); }, cfg);
  CHECK(0.6 - dr_yaw(dr, Time::from_s(60)) == Approx(0.05).margin(0.005));
}

TEST_CASE("the attitude filter restarts on the orientation after an IMU gap", "[unit]") {
  DeadReckoning dr;  // default filter
  for (int k = 0; k <= 100; ++k) {
    const Time t = Time::from_ns(int64_t{k} * 10'000'000);
    dr.add(ImuReading{t, yaw_quat(0.0), Vec3(0.0, 0.0, 1e-4 * jitter(k, 0)), Vec3::Zero()});
    if (k % 20 == 0) dr.add(DvlReading{t, Vec3(0.5, 0, 0), true, 5.0});
  }
  // 2 s without IMU, then the heading is 1 rad: taken at once, not blended in over tau.
  const Time t = Time::from_seconds(3.0);
  dr.add(ImuReading{t, yaw_quat(1.0), Vec3(0.0, 0.0, 1e-4), Vec3::Zero()});
  dr.add(DvlReading{t, Vec3(0.5, 0, 0), true, 5.0});
  CHECK(dr_yaw(dr, t) == Approx(1.0).margin(1e-9));
}

TEST_CASE("without gyro rates the attitude filter stays off", "[unit]") {
  // A device set up without gyro output reports zero rates: a turn must then follow the
  // orientation exactly, not lag behind it by tau.
  const auto dr = run_imu(1000, [](int64_t k) { return 0.001 * static_cast<double>(k); }, [](int64_t) { return 0.0; });
  CHECK(dr_yaw(dr, Time::from_s(10)) == Approx(1.0).margin(1e-9));
}

// Issue 35: a NaN orientation was normalised into NaN and every later pose (and the voxel
// keys of every point placed with it) became NaN; such a reading is skipped and counted.
TEST_CASE("DR skips and counts IMU readings with a non-finite orientation", "[unit]") {
  DeadReckoning dr;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k <= 100; ++k) {
    const Time t = Time::from_ms(10 * k);
    ImuReading r{t, yaw_quat(0.2), Vec3(0.0, 0.0, 0.001), Vec3::Zero()};
    if (k % 10 == 5) r.q_W_V = Quat(nan, 0.0, 0.0, 0.0);
    if (k % 10 == 6) r.q_W_V = Quat(1.0, std::numeric_limits<double>::infinity(), 0.0, 0.0);
    dr.add(r);
    if (k % 20 == 0) {
      dr.add(DepthReading{t, 3.0});
      dr.add(DvlReading{t, Vec3(1.0, 0.0, 0.0), true, 5.0});
    }
  }
  CHECK(dr.counts().imu_nonfinite == 20);
  for (int k = 0; k <= 100; ++k) {
    const auto p = dr.pose_at(Time::from_ms(10 * k));
    REQUIRE(p.ok());
    INFO(k);
    REQUIRE(p->matrix().allFinite());
  }
  CHECK(dr.pose_at(Time::from_s(1))->translation().x() == Approx(std::cos(0.2)).margin(0.01));
}

TEST_CASE("DR's translation sigma follows the DVL's noise figures, and grows over a dropout", "[unit]") {
  DrConfig cfg;
  cfg.dvl_velocity_sigma_mps = 0.01;
  cfg.dvl_scale_sigma = 0.003;
  cfg.dvl_dropout_speed_sigma_mps = 0.5;
  const auto dr = run(40.0, [](double) { return 0.0; }, Vec3(0.5, 0.0, 0.0), [](DvlReading& r) {
    return r.stamp <= Time::from_s(10) || r.stamp > Time::from_s(30);
  }, cfg);
  // 2 s to 8 s: 3 m. White: 0.01 m/s over 6 s at the mean reading interval; scale: 0.003 x 3 m.
  const double scale = 0.003 * 3.0;
  const auto s = dr.translation_sigma_m(Time::from_s(2), Time::from_s(8));
  REQUIRE(s.has_value());
  // The mean interval: 40 s over the readings kept, 51 in [0, 10] and 50 in (30, 40], less one.
  const double mean_period = 40.0 / 100.0;
  CHECK(*s == Approx(std::sqrt(0.01 * 0.01 * 6.0 * mean_period + scale * scale)).epsilon(1e-9));
  CHECK(*s > scale);
  CHECK(*s < 0.05);  // well under sigma_odometry's constant 0.05 m
  // Across the outage (the dropout is [10 s, 30.2 s]): 0.5 m/s unknown over 20 s dominates.
  const auto across = dr.translation_sigma_m(Time::from_s(8), Time::from_s(32));
  REQUIRE(across.has_value());
  CHECK(*across > 0.5 * 20.0);
  CHECK(*across < 0.5 * 20.5);
  // Before two readings or outside the DR span: none.
  CHECK_FALSE(dr.translation_sigma_m(Time::from_s(2), Time::from_s(50)).has_value());
  DeadReckoning empty;
  CHECK_FALSE(empty.translation_sigma_m(Time::from_s(0), Time::from_s(1)).has_value());
}

TEST_CASE("DR forget_before releases old states and changes no later pose, bit for bit", "[unit]") {
  // A turning, speed-varying run with a DVL outage, so poses and sigmas are not trivial.
  const auto yaw = [](double t) { return 0.05 * t + 0.3 * std::sin(0.2 * t); };
  const auto dvl = [](DvlReading& r) {
    r.velocity_V_mps.x() = 0.4 + 0.1 * std::sin(r.stamp.seconds());
    return r.stamp <= Time::from_s(40) || r.stamp > Time::from_s(47);
  };
  const auto whole = run(120.0, yaw, Vec3(0.4, 0.05, 0.0), dvl);
  auto part = run(120.0, yaw, Vec3(0.4, 0.05, 0.0), dvl);
  const size_t before = part.states_kept();
  const Time cut = Time::from_ms(60'123);  // between DVL states (5 Hz)
  part.forget_before(cut);
  CHECK(part.states_kept() == 301);  // 60.0 s to 120 s at 5 Hz
  CHECK(before > 500);
  CHECK(part.memory_bytes() < whole.memory_bytes());
  CHECK(part.kept_from() <= cut);                     // the state before the cut is kept...
  CHECK(part.kept_from() > cut - Time::from_ms(200));  // ...and nothing older
  CHECK(part.first_time() == whole.first_time());     // the first state's stamp is remembered
  CHECK(part.last_time() == whole.last_time());
  for (int64_t ms = 60'123; ms <= 120'000; ms += 37) {
    const Time t = Time::from_ms(ms);
    const auto a = whole.pose_at(t), b = part.pose_at(t);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a->matrix() == b->matrix());
  }
  for (int64_t ms : {60'123, 70'000, 100'500})
    CHECK(*whole.translation_sigma_m(Time::from_ms(ms), Time::from_s(120)) ==
          *part.translation_sigma_m(Time::from_ms(ms), Time::from_s(120)));
  // Before the kept history: an error that says the states were released.
  const auto gone = part.pose_at(Time::from_s(30));
  REQUIRE_FALSE(gone.ok());
  CHECK(gone.error().message.find("released") != std::string::npos);
  CHECK(whole.pose_at(Time::from_s(30)).ok());
  // Forgetting again at an earlier stamp keeps what is held; past the end keeps the last state.
  part.forget_before(Time::from_s(10));
  CHECK(part.kept_from() <= cut);
  part.forget_before(Time::from_s(500));
  CHECK(part.states_kept() == 1);
  CHECK(part.pose_at(Time::from_s(120)).ok());
}
