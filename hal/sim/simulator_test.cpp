#include <catch2/catch.hpp>

#include <cmath>
#include <set>

#include "hal/sim/simulator.hpp"

namespace orthosonar::sim {
namespace {

SimConfig short_config(double duration_s = 3.0) {
  SimConfig c;
  c.duration_s = duration_s;
  c.resolution = Resolution::kReduced;
  c.seed = 11;
  return c;
}

std::vector<Event> drain(Simulator& s) {
  std::vector<Event> out;
  while (true) {
    auto p = s.next();
    REQUIRE(!p.error);
    if (p.end_of_stream) return out;
    out.push_back(std::move(*p.event));
  }
}

}  // namespace

TEST_CASE("simulator events are ordered with per-channel sequences and truth at every stamp", "[hal]") {
  SimConfig cfg = short_config(2.0);
  cfg.labels = true;
  Simulator sim(*builtin_scene("harbor", 1), cfg);
  const auto events = drain(sim);
  REQUIRE(!events.empty());
  std::array<uint64_t, kChannelCount> next{};
  std::set<int64_t> sensor_stamps, truth_stamps;
  for (size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    if (i > 0) CHECK(event_before(events[i - 1], e));
    CHECK(e.sequence == next[static_cast<size_t>(e.channel)]++);
    CHECK(channel_of(e.payload) == e.channel);
    CHECK(stamp_of(e.payload) == e.stamp);
    if (e.channel == Channel::kTruthPose) truth_stamps.insert(e.stamp.ns());
    else if (e.channel <= Channel::kDepth) sensor_stamps.insert(e.stamp.ns());
  }
  CHECK(truth_stamps == sensor_stamps);
  CHECK(next[static_cast<size_t>(Channel::kSonarHorizontal)] == 10u);  // 5 Hz x 2 s
  CHECK(next[static_cast<size_t>(Channel::kLabelsVertical)] == 10u);
  CHECK(next[static_cast<size_t>(Channel::kImu)] == 200u);
  CHECK(next[static_cast<size_t>(Channel::kTruthPose)] == sim.planned_count(Channel::kTruthPose));
  // The vertical ping fires a few ms after the horizontal.
  Time h, v;
  for (const auto& e : events) {
    if (e.channel == Channel::kSonarHorizontal && e.sequence == 3) h = e.stamp;
    if (e.channel == Channel::kSonarVertical && e.sequence == 3) v = e.stamp;
  }
  CHECK((v - h) == Time::from_ms(3));
  const auto md = sim.metadata();
  for (const char* key : {"scene", "seed", "resolution", "duration_s", "T_V_h", "T_V_v", "vehicle_depth_m", "software_version"})
    CHECK(md.count(key) == 1u);
  CHECK(md.at("scene") == "harbor");
  CHECK(md.at("resolution") == "reduced");
  CHECK(parse_pose6(md.at("T_V_v")).ok());
  CHECK(parse_pose6(md.at("T_V_v"))->isApprox(cfg.T_V_v, 1e-12));
}

TEST_CASE("a short mission is deterministic for any render thread count", "[hal]") {
  const Scene scene = *builtin_scene("marina1", 1);
  Simulator a(scene, short_config());
  SimConfig threaded = short_config();
  threaded.render_threads = 3;
  Simulator b(scene, threaded);
  const auto ea = drain(a);
  CHECK(ea == drain(b));
  SimConfig other = short_config();
  other.seed = 12;
  Simulator c(scene, other);
  const auto ec = drain(c);
  REQUIRE(ec.size() == ea.size());
  CHECK(ea != ec);
  // Truth does not depend on the noise seed.
  for (size_t i = 0; i < ea.size(); ++i)
    if (ea[i].channel == Channel::kTruthPose) CHECK(ea[i] == ec[i]);
}

TEST_CASE("navigation sensors have the configured noise and the yaw bias drifts", "[hal]") {
  SimConfig cfg = short_config(120.0);
  cfg.nav.ping_rate_hz = 0.1;  // few pings: this test is about navigation
  Simulator sim(*builtin_scene("aircraft", 1), cfg);
  double depth_sq = 0;
  int depth_n = 0, dvl_invalid = 0, dvl_n = 0;
  double last_yaw_err = 0;
  while (true) {
    auto p = sim.next();
    if (p.end_of_stream) break;
    const Event& e = *p.event;
    if (const auto* d = std::get_if<DepthReading>(&e.payload)) {
      depth_sq += std::pow(d->depth_m - 3.0, 2);
      ++depth_n;
    } else if (const auto* v = std::get_if<DvlReading>(&e.payload)) {
      ++dvl_n;
      if (!v->valid) ++dvl_invalid;
      else CHECK(v->altitude_m == Approx(4.0).margin(1.5));
    } else if (const auto* q = std::get_if<ImuReading>(&e.payload)) {
      const auto truth = sim.trajectory().at(e.stamp);
      last_yaw_err = wrap_angle(yaw_of(q->q_W_V) - truth.yaw_rad);
    }
  }
  CHECK(std::sqrt(depth_sq / depth_n) == Approx(0.02).margin(0.005));
  CHECK(dvl_invalid > 0);
  CHECK(dvl_invalid < dvl_n / 10);
  // Steady drift 0.004 deg/s over 120 s ~ 0.48 deg plus the walk: clearly non-zero.
  CHECK(std::abs(last_yaw_err) > 0.1 * std::numbers::pi / 180.0);
}

TEST_CASE("the vehicle follows the route at its speed and depth", "[hal]") {
  const Scene scene = *builtin_scene("harbor", 1);
  const Trajectory t(scene.route, scene.vehicle_depth_m, VehicleConfig{}, Time::from_s(300));
  CHECK(t.path_length_m() == Approx(300 * 0.4).margin(15.0));
  const auto s = t.at(Time::from_s(200));
  CHECK(s.p_W.z() == Approx(-3.0));
  CHECK(s.p_W.x() > scene.route[0].x_m + 40);
  double max_rate = 0;
  for (int k = 0; k < 3000; ++k) max_rate = std::max(max_rate, std::abs(t.at(Time::from_ms(100 * k)).omega_V_rps.z()));
  CHECK(max_rate <= VehicleConfig{}.max_yaw_rate_dps * std::numbers::pi / 180.0 + 1e-9);
}

}  // namespace orthosonar::sim

// Found by fuzz_sim_config (2026-12-01): "? :" (a YAML key with no key) under a section threw
// yaml-cpp's TypedBadConversion out of apply_sim_config_yaml.
TEST_CASE("sim config keys that are not plain names are errors, not exceptions", "[hal]") {
  for (const std::string text : {"sonar:\n  ? :\n", "? :\n", "[1]: 2\n", "nav: {? [a]: 1}\n"}) {
    orthosonar::sim::SimConfig c;
    orthosonar::Status s = orthosonar::Status::Ok();
    REQUIRE_NOTHROW(s = orthosonar::sim::apply_sim_config_yaml(text, c));
    INFO(text);
    CHECK_FALSE(s.ok());
  }
}

