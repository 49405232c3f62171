// The graph's heading (docs/SLAM.md): on an AHRS the heading gate and the drift state
// (issue 33), and the FOG's DR factor (issue 32): scan matches that add little, the loop
// heading gate, translation-only loops and the loop sigma's growth with length.
#include "core/slam/keyframe_slam.hpp"

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "core/slam/synthetic.hpp"
#include "core/slam/test_support.hpp"

using namespace orthosonar;
using namespace orthosonar::slam;
using namespace orthosonar::slam::testing;

TEST_CASE("On an AHRS a loop turned further than the chain can have drifted is no candidate", "[unit]") {
  // As above, but five keyframes' scans are turned by 9 degrees and barely moved: the joint
  // gate (off here, and loose on an AHRS with sigma_loop's 0.05 rad) and PCM let such loops
  // through; the heading gate (nssm_max_heading_sigmas) tests the heading alone against the
  // chain's heading sigma and one scan match's (docs/SLAM.md "Heading drift on the AHRS").
  const auto world = make_basin_world(5);
  const auto truth = loop_route(30.0, 20.0, 3.0, 2);
  const auto dr = drifting_odometry(truth, 0.0, 0.0002, 0.01, 9);
  const size_t first_bad = truth.size() / 2 + 2, last_bad = first_bad + 4;
  const SE2 turned{0.1, 0.0, 0.157};
  const auto fly = [&](const SlamConfig& config) {
    return fly_misplaced(config, world, truth, dr, first_bad, last_bad, turned);
  };
  const auto turned_loops = [&](const KeyframeSlam& slam, bool accepted) {
    int n = 0;
    for (const auto& f : slam.factors()) {
      n += f.kind == FactorKind::kLoopClosure && f.accepted == accepted && f.to >= static_cast<int>(first_bad) &&
           f.to <= static_cast<int>(last_bad) && std::abs(wrap_angle(f.T_from_to.theta - (dr[static_cast<size_t>(f.from)].inverse() * dr[static_cast<size_t>(f.to)]).theta)) > 0.1;
    }
    return n;
  };
  SlamConfig off;
  off.nssm_max_mahalanobis = 0.0;
  off.nssm_max_heading_sigmas = 0.0;
  off.loop_loss = GraphEdge::Loss::kNone;
  SlamConfig gated = off;
  gated.nssm_max_heading_sigmas = 3.0;
  const KeyframeSlam without = fly(off), with = fly(gated);
  int rejected = 0;
  for (const auto& f : with.factors()) rejected += f.reason.rfind("loop disagrees with the odometry chain", 0) == 0;
  INFO("turned loops accepted without the gate " << turned_loops(without, true) << ", with it "
       << turned_loops(with, true) << "; rejected by it " << rejected << "; loops accepted "
       << without.accepted_loop_closures() << " -> " << with.accepted_loop_closures());
  CHECK(turned_loops(without, true) >= 2);
  CHECK(turned_loops(with, true) == 0);
  CHECK(rejected >= 2);
  CHECK(with.accepted_loop_closures() >= 1);  // the honest loops still close
}

TEST_CASE("The heading drift state is on for an AHRS heading by default and off with a gyro", "[unit]") {
  const SlamConfig c;
  CHECK(c.heading_drift_sigma_dps > 0.0);
  CHECK(c.heading_drift_sigma_gyro_dps == 0.0);
  const auto world = make_basin_world(5);
  const auto truth = loop_route(30.0, 20.0, 3.0, 2);
  // 0.003 rad per keyframe, keyframes 20 s apart: 1.5e-4 rad/s (0.0086 deg/s)
  const auto dr = drifting_odometry(truth, 0.003, 0.0002, 0.01, 9);
  const auto fly = [&](bool gyro) {
    KeyframeSlam slam(c);
    for (size_t i = 0; i < truth.size(); ++i) {
      KeyframeSlam::DrSigma s;
      if (gyro) {
        s.heading_rad = 1e-4;
        s.translation_m = 0.02;
      }
      slam.add_keyframe(Time::from_s(20 * static_cast<int64_t>(i)), se3(dr[i]), synthetic_scan_V(world, truth[i], {}, 1, i), s);
    }
    CHECK(slam.drift_sigma_dps() == (gyro ? 0.0 : c.heading_drift_sigma_dps));
    return slam.heading_drift_rad_s();
  };
  const double ahrs = fly(false), gyro = fly(true);
  INFO("rate found on the AHRS " << ahrs << " rad/s (simulated 1.5e-4), with a gyro " << gyro);
  CHECK(ahrs > 0.5 * 1.5e-4);
  CHECK(gyro == 0.0);
}

TEST_CASE("Heading links hold a chain of heading-biased scan matches to the DR heading", "[unit]") {
  // Scans taken as if the vehicle turned 0.5 deg more per keyframe than it did (a biased
  // one-sided match, docs/SLAM.md "Heading links"); DR's heading nearly exact; no loop
  // closures (min_pcm out of reach), so only the odometry chain and the links decide.
  const auto world = make_basin_world(5);
  auto truth = loop_route(30.0, 20.0, 2.0, 1);
  truth.resize(40);
  const auto dr = drifting_odometry(truth, 0.0, 0.0002, 0.01, 9);
  const double bias = 0.5 * std::numbers::pi / 180.0;
  const auto fly = [&](const SlamConfig& config) {
    KeyframeSlam slam(config);
    for (size_t i = 0; i < truth.size(); ++i) {
      const SE2 seen = truth[i] * SE2{0.0, 0.0, bias * static_cast<double>(i)};
      slam.add_keyframe(Time::from_s(static_cast<int64_t>(i)), se3(dr[i]), synthetic_scan_V(world, seen, {}, 1, i));
      REQUIRE(slam.last_solve().usable);
    }
    return slam;
  };
  const auto worst_heading_error = [&](const KeyframeSlam& slam) {
    double worst = 0.0;
    for (size_t i = 0; i < truth.size(); ++i)
      worst = std::max(worst, std::abs(wrap_angle(se2_from_se3(slam.keyframes()[i].T_W_V_slam).theta - truth[i].theta)));
    return worst;
  };
  SlamConfig off;
  off.min_pcm = 1000;
  SlamConfig linked = off;
  linked.heading_link_s = 10.0;
  const KeyframeSlam without = fly(off), with = fly(linked);
  int links = 0;
  for (const auto& f : with.factors()) {
    if (f.kind != FactorKind::kHeadingLink) continue;
    ++links;
    CHECK(f.accepted);
    CHECK(f.to - f.from == 10);  // one link per 10 s of keyframe time, chained
    CHECK(f.mix.topRows<2>().isZero());  // yaw only
  }
  for (const auto& f : without.factors()) CHECK(f.kind != FactorKind::kHeadingLink);
  const double e_without = worst_heading_error(without), e_with = worst_heading_error(with);
  INFO("worst SLAM heading error without links " << e_without * 180.0 / std::numbers::pi << " deg, with "
       << e_with * 180.0 / std::numbers::pi << " deg; links " << links);
  CHECK(links == 3);
  CHECK(e_without > 1.0 * std::numbers::pi / 180.0);  // the biased chain turns SLAM by 1.5 deg
  CHECK(e_with < 0.5 * e_without);
}

TEST_CASE("With the DR factor from a FOG and a DVL, scan matches that add little are recorded, not added", "[unit]") {
  // The synthetic basin, DR good in heading and translation (a FOG and a DVL). With the
  // sensors' sigmas (a few per cent of the scan matches' information in every direction) the
  // sequential matches are left out; with the constant sigma_odometry they are added.
  const auto world = make_basin_world(5);
  const auto truth = loop_route(30.0, 20.0, 3.0, 1);
  const auto dr = drifting_odometry(truth, 0.003, 0.0, 0.0, 9);
  auto fly = [&](SlamConfig::DrSigmaModel model, KeyframeSlam::DrSigma sigma) {
    SlamConfig config;
    config.dr_sigma_model = model;
    KeyframeSlam slam(config);
    for (size_t i = 0; i < truth.size(); ++i)
      slam.add_keyframe(Time::from_s(static_cast<int64_t>(i)), se3(dr[i]), synthetic_scan_V(world, truth[i], {}, 1, i),
                        i == 0 ? KeyframeSlam::DrSigma{} : sigma);
    size_t icp_added = 0, icp_little = 0;
    for (const auto& f : slam.factors()) {
      if (f.kind != FactorKind::kSequentialIcp) continue;
      icp_added += f.accepted ? 1 : 0;
      icp_little += f.reason.find("adds under 10 %") != std::string::npos ? 1 : 0;
    }
    CHECK(graph_connected(slam));
    return std::pair{icp_added, icp_little};
  };
  const KeyframeSlam::DrSigma fog{0.015, 0.0002};
  const auto [added_auto, little_auto] = fly(SlamConfig::DrSigmaModel::kAuto, fog);
  CHECK(added_auto == 0);
  CHECK(little_auto > 10);
  const auto [added_const, little_const] = fly(SlamConfig::DrSigmaModel::kConstant, fog);
  CHECK(added_const > 10);
  CHECK(little_const == 0);
  // Without a gyro heading, auto keeps the constant: the matches are added.
  const auto [added_ahrs, little_ahrs] = fly(SlamConfig::DrSigmaModel::kAuto, KeyframeSlam::DrSigma{0.015, std::nullopt});
  CHECK(added_ahrs > 10);
  CHECK(little_ahrs == 0);
}

TEST_CASE("With a FOG's DR factor, loops turned from the odometry chain by more than the gate are no candidates", "[unit]") {
  // Two laps of the basin with FOG-grade DR: the loop matches are within a tenth of a degree
  // of the chain and pass the 0.5 deg gate; a gate of 1e-4 deg refuses every one, and
  // without a gyro heading (the AHRS graph) the gate does not apply.
  auto fly = [](double gate_deg, std::optional<double> heading_sigma) {
    SlamConfig config;
    config.nssm_max_heading_diff_gyro_deg = gate_deg;
    return fly_basin(config, 2, {0.015, heading_sigma}).accepted_loop_closures();
  };
  CHECK(fly(0.5, 0.0002) >= 1);
  CHECK(fly(1e-4, 0.0002) == 0);
  CHECK(fly(1e-4, std::nullopt) >= 1);
}

TEST_CASE("With a FOG's DR factor and nssm_fixed_heading_gyro, loops are translation-only fits at the chain's heading", "[unit]") {
  // The two laps of the test above: every loop candidate's measured heading is the graph's
  // relative heading at the time and its heading carries no information (weight 0 in the
  // residual mix); without a gyro heading the option does nothing.
  SlamConfig config;
  config.nssm_fixed_heading_gyro = true;
  const KeyframeSlam fog = fly_basin(config, 2, {0.015, 0.0002});
  size_t fitted = 0;
  for (const auto& f : fog.factors()) {
    if (f.kind != FactorKind::kLoopClosure || !f.accepted) continue;
    ++fitted;
    CHECK(f.weakened >= 1);
    CHECK(f.mix.row(2).isZero(0.0));
    CHECK(f.mix.col(2).isZero(0.0));
    CHECK(f.information()(2, 2) == 0.0);
  }
  CHECK(fitted >= 1);
  CHECK(fog.accepted_loop_closures() >= 1);
  const KeyframeSlam ahrs = fly_basin(config, 2, {0.015, std::nullopt});
  for (const auto& f : ahrs.factors())
    if (f.kind == FactorKind::kLoopClosure && f.accepted) CHECK_FALSE(f.mix.row(2).isZero(0.0));
  CHECK(ahrs.accepted_loop_closures() >= 1);
}

TEST_CASE("With a FOG's DR factor a loop's x/y sigma grows with its length (sigma_loop_per_m), without one it does not",
          "[unit]") {
  // Two laps of the basin: every loop factor's x/y sigma is hypot(sigma_loop_gyro, k |t|), t
  // its measured translation; 0 leaves them at sigma_loop_gyro; the AHRS graph keeps sigma_loop.
  SlamConfig config;
  config.sigma_loop_per_m = 0.05;
  const KeyframeSlam fog = fly_basin(config, 2, {0.015, 0.0002});
  size_t loops = 0;
  double longest = 0.0;
  for (const auto& f : fog.factors()) {
    if (f.kind != FactorKind::kLoopClosure) continue;
    ++loops;
    const double length = std::hypot(f.T_from_to.x, f.T_from_to.y);
    longest = std::max(longest, length);
    const double expected = std::hypot(config.sigma_loop_gyro.x(), 0.05 * length);
    CHECK(f.sigma.x() == Approx(expected));
    CHECK(f.sigma.y() == Approx(std::hypot(config.sigma_loop_gyro.y(), 0.05 * length)));
    CHECK(f.sigma.z() == config.sigma_loop_gyro.z());
  }
  REQUIRE(loops >= 1);
  CHECK(longest > 1.0);  // the growth is exercised, not only its zero
  config.sigma_loop_per_m = 0.0;
  const KeyframeSlam off = fly_basin(config, 2, {0.015, 0.0002});  // named: factors() is a member
  for (const auto& f : off.factors())
    if (f.kind == FactorKind::kLoopClosure) CHECK(f.sigma == config.sigma_loop_gyro);
  config.sigma_loop_per_m = 0.05;
  const KeyframeSlam ahrs = fly_basin(config, 2, {0.015, std::nullopt});
  for (const auto& f : ahrs.factors())
    if (f.kind == FactorKind::kLoopClosure) CHECK(f.sigma == config.sigma_loop);
}
