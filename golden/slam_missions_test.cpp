// SLAM on simulated missions (issue 6): the simulator (ground truth), CFAR on the
// horizontal sonar, dead reckoning and keyframe SLAM, as the pipeline chains them. Reduced
// resolution and 1 Hz pings keep it fast; keyframes need a ping only every few metres.
#include <catch2/catch.hpp>
#include <cstdio>
#include <deque>
#include <string>
#include <type_traits>

#include "core/perception/cfar.hpp"
#include "core/perception/fusion.hpp"
#include "core/slam/dead_reckoning.hpp"
#include "core/slam/keyframe_slam.hpp"
#include "core/slam/trajectory_error.hpp"
#include "hal/sim/simulator.hpp"

using namespace orthosonar;

namespace {

struct MissionSetup {
  std::string scene;
  double duration_s = 600.0;
  // A consumer-grade heading reference: a steady yaw drift of 3 deg/min plus a random walk
  // (SPEC §10's bias model, magnitudes raised so DR drift is clearly measurable in one
  // or two laps; at the simulator's defaults DR is within ~0.6 m after a lap).
  double yaw_bias_rate_dps = 0.05;
  double yaw_bias_walk_deg_per_sqrt_s = 0.05;
  double speed_mps = 0.5;
  double dvl_outage_from_s = -1.0;  // drop every DVL reading in [from, to)
  double dvl_outage_to_s = -1.0;
};

struct MissionResult {
  size_t keyframes = 0;
  size_t loops = 0;
  double ate_dr = 0.0;
  double ate_slam = 0.0;
  bool connected = true;
  slam::DrCounts dr_counts;
};

slam::SlamConfig mission_slam_config() {
  slam::SlamConfig c;
  // SPEC §5 says >= 5 neighbours; on the simulator's reduced-resolution images (as of
  // this writing) that left 0-10 points per keyframe (pilings are 1-3 voxels), later gave no
  // gain on marina1. 2 is sonar-SLAM's value (feature.yaml min_points). See docs/SLAM.md.
  c.outlier_min_neighbours = 2;
  // These missions model a consumer-grade heading reference (above), so SSM runs as SPEC §5
  // writes it: the DR factor (sonar-SLAM's noise) only where ICP fails. The defaults are
  // matched to the simulator's default IMU instead (docs/SLAM.md "Noise models").
  c.sigma_odometry = Eigen::Vector3d(0.2, 0.2, 0.02);
  c.ssm_keep_dr_factor = false;
  return c;
}

MissionResult run_mission(const MissionSetup& m, const slam::SlamConfig& slam_config) {
  auto scene = sim::builtin_scene(m.scene, 1);
  REQUIRE(scene.ok());
  sim::SimConfig cfg;
  cfg.duration_s = m.duration_s;
  cfg.seed = 3;
  cfg.resolution = sim::Resolution::kReduced;
  cfg.nav.ping_rate_hz = 1.0;
  cfg.nav.imu_yaw_bias_rate_dps = m.yaw_bias_rate_dps;
  cfg.nav.imu_yaw_bias_walk_deg_per_sqrt_s = m.yaw_bias_walk_deg_per_sqrt_s;
  cfg.vehicle.speed_mps = m.speed_mps;
  sim::Simulator simulator(std::move(*scene), cfg);

  slam::DeadReckoning dr;
  slam::KeyframeSlam slam(slam_config);
  const perception::CfarConfig cfar;
  std::deque<SonarPing> pending;
  std::vector<TruthPose> truth;
  const Time outage_from = Time::from_seconds(m.dvl_outage_from_s);
  const Time outage_to = Time::from_seconds(m.dvl_outage_to_s);
  const auto place = [&](bool final) {
    while (!pending.empty() && (final || (!dr.empty() && pending.front().stamp <= dr.last_time()))) {
      const SonarPing ping = std::move(pending.front());
      pending.pop_front();
      const auto pose = dr.pose_at(ping.stamp);
      if (!pose.ok() || !slam.should_add(*pose)) continue;
      const auto dets = perception::cfar_detect(ping, cfar);
      slam.add_keyframe(ping.stamp, *pose, perception::planar_points_V(ping, dets, cfg.T_V_h));
    }
  };
  for (;;) {
    auto pulled = simulator.next();
    REQUIRE_FALSE(pulled.error.has_value());
    if (pulled.end_of_stream) break;
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, DvlReading>) {
            if (!(x.stamp >= outage_from && x.stamp < outage_to)) dr.add(x);
          } else if constexpr (std::is_same_v<T, ImuReading> || std::is_same_v<T, DepthReading>) {
            dr.add(x);
          } else if constexpr (std::is_same_v<T, TruthPose>) {
            if (truth.empty() || truth.back().stamp < x.stamp) truth.push_back(x);
          } else if constexpr (std::is_same_v<T, SonarPing>) {
            if (x.mount == SonarMount::kHorizontal) pending.push_back(x);
          }
        },
        pulled.event->payload);
    place(false);
  }
  place(true);

  MissionResult r;
  r.keyframes = slam.keyframes().size();
  r.loops = slam.accepted_loop_closures();
  r.dr_counts = dr.counts();
  std::vector<Vec3> p_truth, p_dr, p_slam;
  size_t ti = 0;
  for (const auto& kf : slam.keyframes()) {
    // Truth is sampled at every sensor stamp, so each keyframe's ping stamp has one.
    while (ti + 1 < truth.size() && truth[ti + 1].stamp <= kf.stamp) ++ti;
    REQUIRE(truth[ti].stamp == kf.stamp);
    p_truth.push_back(truth[ti].p_W);
    p_dr.push_back(kf.T_W_V_dr.translation());
    p_slam.push_back(kf.T_W_V_slam.translation());
  }
  r.ate_dr = slam::ate_rmse(p_dr, p_truth);
  r.ate_slam = slam::ate_rmse(p_slam, p_truth);
  for (size_t k = 1; k < slam.keyframes().size(); ++k) {
    bool linked = false;
    for (const auto& f : slam.factors()) {
      linked |= f.accepted && f.from + 1 == f.to && f.to == static_cast<int>(k) &&
                (f.kind == slam::FactorKind::kSequentialIcp || f.kind == slam::FactorKind::kOdometryDr);
    }
    r.connected &= linked;
  }
  std::printf("slam mission %s %.0f s: keyframes %zu, loop closures %zu, ATE DR %.3f m, SLAM %.3f m\n",
              m.scene.c_str(), m.duration_s, r.keyframes, r.loops, r.ate_dr, r.ate_slam);
  return r;
}

}  // namespace

TEST_CASE("marina1 two laps: SLAM ATE at most half of DR with a loop closure", "[golden]") {
  const auto r = run_mission({"marina1", 840.0}, mission_slam_config());
  CHECK(r.connected);
  CHECK(r.loops >= 1);
  CHECK(r.ate_dr > 1.0);
  CHECK(r.ate_slam <= 0.5 * r.ate_dr);
}

TEST_CASE("harbor beyond one lap: SLAM ATE at most half of DR with a loop closure", "[golden]") {
  const auto r = run_mission({"harbor", 1000.0}, mission_slam_config());
  CHECK(r.connected);
  CHECK(r.loops >= 1);
  CHECK(r.ate_dr > 1.0);
  CHECK(r.ate_slam <= 0.5 * r.ate_dr);
}

TEST_CASE("A 20 s DVL outage in a marina1 mission: no crash and a connected graph", "[golden]") {
  MissionSetup m{"marina1", 200.0};
  m.dvl_outage_from_s = 90.0;
  m.dvl_outage_to_s = 110.0;
  const auto r = run_mission(m, mission_slam_config());
  CHECK(r.connected);
  CHECK(r.keyframes > 20);
  REQUIRE(r.dr_counts.dropouts == 1);
  CHECK(r.dr_counts.gaps[0].first < Time::from_s(90));
  CHECK(r.dr_counts.gaps[0].second >= Time::from_s(110));
}

// The figures for docs/SLAM.md (all four scenes, defaults and the mission config). Slow:
// run on demand with `orthosonar_golden_tests "[slam-table]"`.
TEST_CASE("SLAM and DR ATE on all four scenes", "[.][slam-table]") {
  for (const char* scene : {"marina1", "marina2", "harbor", "aircraft"}) {
    const auto r = run_mission({scene, 1000.0}, mission_slam_config());
    CHECK(r.connected);
    const auto d = run_mission({scene, 1000.0}, slam::SlamConfig{});
    CHECK(d.connected);
  }
}
