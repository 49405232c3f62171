// SLAM on simulated missions through the product's path (issue 20): the simulator is the
// event source of run::run_source, so dead reckoning, CFAR, keyframe SLAM and fusion run in
// mapping::Pipeline exactly as `orthosonar replay` runs them, with the run configuration's
// defaults unless a mission says otherwise. ATE is the run's own (keyframe positions against
// the truth stream). Reduced resolution keeps it fast; the figures are in docs/SLAM.md.
#include <catch2/catch.hpp>
#include <cstdio>
#include <numbers>
#include <string>

#include "hal/sim/simulator.hpp"
#include "replay/run/run.hpp"

using namespace orthosonar;

namespace {

struct Mission {
  std::string scene;
  double duration_s = 600.0;
  uint64_t seed = 3;
  // A consumer-grade heading reference: a steady yaw drift of 3 deg/min plus a random walk
  // (SPEC §10's bias model, magnitudes raised so DR drift is clearly measurable in a lap).
  bool consumer_heading = false;
  // These missions measure SLAM against a drifting heading: the AHRS alone (the simulator's
  // default before 2026-12-05 is the paper's vehicle, whose FOG leaves DR little to correct).
  sim::NavProfile nav = sim::NavProfile::kAhrs;
  std::string run_yaml;             // the run configuration (docs/CONFIG.md); empty: defaults
  double dvl_outage_from_s = -1.0;  // drop every DVL reading in [from, to)
  double dvl_outage_to_s = -1.0;
};

struct Outcome {
  size_t keyframes = 0;
  size_t loops = 0;
  double ate_dr = 0.0;
  double ate_slam = 0.0;
  bool connected = true;
  double drift_dps = 0.0;  // the estimated heading drift (slam.heading_drift_sigma_dps > 0)
  // Keyframe heading against the truth, RMS in degrees (issue 33; metrics.json's
  // heading_error_dr / heading_error_slam).
  double heading_rms_dr_deg = 0.0, heading_rms_slam_deg = 0.0;
  slam::DrCounts dr_counts;
};

// The simulator with a window of DVL readings removed (a DVL outage), as a source.
class DvlOutage final : public hal::EventSource {
 public:
  DvlOutage(hal::EventSource& inner, Time from, Time to) : inner_(inner), from_(from), to_(to) {}
  hal::Pulled next() override {
    for (;;) {
      hal::Pulled p = inner_.next();
      if (p.event && p.event->channel == Channel::kDvl && p.event->stamp >= from_ && p.event->stamp < to_) continue;
      return p;
    }
  }
  std::string describe() const override { return inner_.describe() + " (dvl outage)"; }

 private:
  hal::EventSource& inner_;
  Time from_, to_;
};

Outcome fly(const Mission& m) {
  auto scene = sim::builtin_scene(m.scene, 1);
  REQUIRE(scene.ok());
  sim::SimConfig cfg;
  cfg.duration_s = m.duration_s;
  cfg.seed = m.seed;
  cfg.resolution = sim::Resolution::kReduced;
  cfg.render_threads = 2;
  cfg.nav_profile = m.nav;
  sim::apply_nav_profile(cfg.nav, m.nav);
  if (m.consumer_heading) {
    cfg.nav.imu_yaw_bias_rate_dps = 0.05;
    cfg.nav.imu_yaw_bias_walk_deg_per_sqrt_s = 0.05;
  }
  sim::Simulator simulator(std::move(*scene), cfg);
  DvlOutage source(simulator, Time::from_seconds(m.dvl_outage_from_s), Time::from_seconds(m.dvl_outage_to_s));
  const auto metadata = simulator.metadata();

  run::RunOptions options;
  options.config_yaml = m.run_yaml;
  options.config_origin = "mission";
  options.systems = {"fusion"};
  auto config = run::effective_config(metadata, options);  // DR start from the mission plan
  REQUIRE(config.ok());
  options.config = *config;
  auto r = run::run_source(source, metadata, options, std::nullopt);
  REQUIRE(r.ok());
  REQUIRE(r->ate_dr_m.has_value());
  REQUIRE(r->ate_slam_m.has_value());
  REQUIRE(r->heading_dr.has_value());
  REQUIRE(r->heading_slam.has_value());

  Outcome o;
  o.heading_rms_dr_deg = r->heading_dr->rms_deg;
  o.heading_rms_slam_deg = r->heading_slam->rms_deg;
  const slam::KeyframeSlam& slam = r->pipeline->slam();
  o.keyframes = slam.keyframes().size();
  o.loops = slam.accepted_loop_closures();
  o.ate_dr = *r->ate_dr_m;
  o.ate_slam = *r->ate_slam_m;
  o.drift_dps = slam.heading_drift_rad_s() * 180.0 / std::numbers::pi;
  o.dr_counts = r->pipeline->dead_reckoning().counts();
  for (size_t k = 1; k < slam.keyframes().size(); ++k) {
    bool linked = false;
    for (const auto& f : slam.factors()) {
      linked |= f.accepted && f.from + 1 == f.to && f.to == static_cast<int>(k) &&
                (f.kind == slam::FactorKind::kSequentialIcp || f.kind == slam::FactorKind::kOdometryDr);
    }
    o.connected &= linked;
  }
  std::printf("slam mission %s %.0f s seed %llu%s: keyframes %zu, loop closures %zu, ATE DR %.3f m, SLAM %.3f m, "
              "heading RMS DR %.3f deg, SLAM %.3f deg, drift %.4f deg/s\n",
              m.scene.c_str(), m.duration_s, static_cast<unsigned long long>(m.seed),
              m.consumer_heading ? " (consumer heading)" : "", o.keyframes, o.loops, o.ate_dr, o.ate_slam,
              o.heading_rms_dr_deg, o.heading_rms_slam_deg, o.drift_dps);
  return o;
}

Mission mission(std::string scene, double duration_s, uint64_t seed = 3) {
  Mission m;
  m.scene = std::move(scene);
  m.duration_s = duration_s;
  m.seed = seed;
  return m;
}

// SPEC §5's noise as written.
constexpr const char* kPoorHeadingConfig = "slam: {sigma_odometry: [0.2, 0.2, 0.02], ssm_keep_dr_factor: false}";
// docs/CONFIG.md "A navigation suite with a poorer heading reference": the DR heading's
// drift estimated in the graph (docs/SLAM.md "Heading drift").
constexpr const char* kDriftConfig =
    "slam: {heading_drift_sigma_dps: 0.05, heading_drift_every_keyframes: 10, nssm_min_points: 50}";

}  // namespace

// The drifting AHRS (navigation profile ahrs, the simulator's default until 2026-12-05) and
// the default configuration.
// Seed 1: before scan matches knew their degenerate directions (docs/SLAM.md "Degenerate scan
// matches") SLAM was 2.15 m here, worse than DR's 1.45 m. (Seed 3 has long stretches without
// structure in range, where SLAM can only follow DR: DR 2.86 m, SLAM 2.13 m; issue 20.)
// Since loop closures need 25 points instead of 50 (2026-12-03) this mission closes 11 loops
// on the hull and SLAM is 0.65 m here (0.31 m without them), while the 20 full-resolution
// fixtures of docs/RESULTS.md improved: a known regression of this mission, bounded at 0.7 m.
// Keyframe heading (issue 33; recorded 2026-12-07: DR 1.39 deg RMS, SLAM 0.54 deg).
// Since 2026-12-08 the graph estimates the AHRS's heading drift and tests each loop's heading
// against the chain by default (docs/SLAM.md "Heading drift on the AHRS"), and this seed is
// the draw where that costs: 0.64 -> 0.90 m, heading 0.54 -> 0.80 deg. On seeds 1-4 of this
// mission together it gains (SLAM ATE 0.64 / 3.99 / 0.82 / 0.63 m -> 0.90 / 0.44 / 0.86 /
// 0.55 m; seed 2 is the next test), as on the 27 full-resolution fixtures of the same page.
// Bounded where it is now: 1.0 m and 0.7 x DR, 0.9 deg and 0.65 x DR's heading. Issue 33's
// 0.3 deg is not met here.
TEST_CASE("harbor beyond one lap, drifting AHRS: SLAM within 1.0 m of truth and at most 0.7 of DR", "[golden]") {
  const auto r = fly(mission("harbor", 1000.0, 1));
  CHECK(r.connected);
  CHECK(r.ate_slam <= 1.0);
  CHECK(r.ate_slam <= 0.7 * r.ate_dr);
  CHECK(r.heading_rms_slam_deg <= 0.9);
  CHECK(r.heading_rms_slam_deg <= 0.65 * r.heading_rms_dr_deg);
}

// The same mission on seed 2, whose AHRS drifts most (DR heading 3.67 deg RMS, 4.83 m ATE):
// without the drift state SLAM followed it (3.99 m, heading 2.78 deg); with it the rate
// comes out of the loops on the hull and SLAM is 0.44 m, heading 0.51 deg (2026-12-08).
TEST_CASE("harbor beyond one lap, seed 2, drifting AHRS: the drift taken out, SLAM within 0.6 m of truth", "[golden]") {
  const auto r = fly(mission("harbor", 1000.0, 2));
  CHECK(r.connected);
  CHECK(r.drift_dps > 0.0);
  CHECK(r.ate_slam <= 0.6);
  CHECK(r.ate_slam <= 0.2 * r.ate_dr);
  CHECK(r.heading_rms_slam_deg <= 0.7);
  CHECK(r.heading_rms_slam_deg <= 0.25 * r.heading_rms_dr_deg);
}

// Keyframe heading (recorded 2026-12-07: DR 1.89 deg RMS, SLAM 0.44 deg): bounded at 0.5 deg
// and a third of DR's; issue 33's 0.3 deg is not met here either.
TEST_CASE("marina1 two laps, drifting AHRS: SLAM within 0.35 m of truth and at most half of DR", "[golden]") {
  const auto r = fly(mission("marina1", 840.0));
  CHECK(r.connected);
  CHECK(r.loops >= 1);
  CHECK(r.ate_slam <= 0.35);
  CHECK(r.ate_slam <= 0.5 * r.ate_dr);
  CHECK(r.heading_rms_slam_deg <= 0.5);
  CHECK(r.heading_rms_slam_deg <= r.heading_rms_dr_deg / 3.0);
}

// A consumer-grade heading with the configuration documented for it (docs/CONFIG.md): the
// simulated 0.05 deg/s drift is found and taken out of DR's yaw, so the consumer-grade
// heading maps as well as the default one. (SPEC §5's noise, documented for it before, gave
// 0.364 m here; it stays in the "[slam-table]" runs below.)
TEST_CASE("marina1 two laps, consumer-grade heading, drift estimated: the rate found, SLAM within 0.3 m", "[golden]") {
  Mission m = mission("marina1", 840.0);
  m.consumer_heading = true;
  m.run_yaml = kDriftConfig;
  const auto r = fly(m);
  CHECK(r.connected);
  CHECK(r.loops >= 1);
  CHECK(r.ate_dr > 1.0);
  CHECK(r.ate_slam <= 0.3);
  CHECK(r.ate_slam <= 0.1 * r.ate_dr);
  CHECK(std::abs(r.drift_dps - 0.05) <= 0.01);
  // The heading with the drift taken out (recorded 2026-12-07: DR 23.8 deg RMS, SLAM 0.29).
  CHECK(r.heading_rms_slam_deg <= 0.35);
}

// The paper's vehicle (the simulator's default): the FOG holds DR's heading, the DR factor
// carries the DVL's noise figures and scan matches that add little are left out, so SLAM
// may only improve on DR (loop closures) and must never lose to it (issue 32).
TEST_CASE("marina1 two laps, the paper's vehicle (defaults): SLAM no worse than DR, within 0.15 m", "[golden]") {
  Mission m = mission("marina1", 840.0);
  m.nav = sim::NavProfile::kPaper;
  const auto r = fly(m);
  CHECK(r.connected);
  CHECK(r.loops >= 1);
  CHECK(r.ate_slam <= r.ate_dr);
  CHECK(r.ate_slam <= 0.15);
  CHECK(r.dr_counts.gyro.used > 200000);
  // The FOG's heading, which the graph must not spoil (recorded 2026-12-07: DR 0.067 deg
  // RMS, SLAM 0.065 deg).
  CHECK(r.heading_rms_dr_deg <= 0.1);
  CHECK(r.heading_rms_slam_deg <= r.heading_rms_dr_deg + 0.01);
}

// With the paper's vehicle: the DVL's translation sigma grows over the outage (DR there is a
// guess), so the graph still connects across it.
TEST_CASE("A 20 s DVL outage in a marina1 mission: no crash, a connected graph, the gap reported", "[golden]") {
  Mission m = mission("marina1", 200.0);
  m.nav = sim::NavProfile::kPaper;
  m.dvl_outage_from_s = 90.0;
  m.dvl_outage_to_s = 110.0;
  const auto r = fly(m);
  CHECK(r.connected);
  CHECK(r.keyframes > 20);
  REQUIRE(r.dr_counts.dropouts == 1);
  CHECK(r.dr_counts.gaps[0].first < Time::from_s(90));
  CHECK(r.dr_counts.gaps[0].second >= Time::from_s(110));
}

// The figures for docs/SLAM.md (all four scenes, both navigation grades). Slow: run on
// demand with `orthosonar_golden_tests "[slam-table]"`.
TEST_CASE("SLAM and DR ATE on all four scenes", "[.][slam-table]") {
  for (const char* scene : {"marina1", "marina2", "harbor", "aircraft"}) {
    for (uint64_t seed : {3, 4}) {
      Mission d = mission(scene, 1000.0, seed);
      CHECK(fly(d).connected);
      Mission c = d;
      c.consumer_heading = true;
      c.run_yaml = kPoorHeadingConfig;
      CHECK(fly(c).connected);
      c.run_yaml = kDriftConfig;
      CHECK(fly(c).connected);
    }
  }
}
