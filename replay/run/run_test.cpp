// The run API (replay/run/run.hpp) in-process: one digest for 1, 2, 4 and 8 fusion
// threads and over repeated runs; progress and cancellation; an exception in a fusion
// task (a worker thread) comes back as an Error; the configuration's precedence (defaults <
// fixture < --config < flags); every configuration key's range is checked with the key
// named in the error.
#include <catch2/catch.hpp>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include "replay/fixture/testing.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/run/mission.hpp"
#include "replay/run/run.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;

namespace {

fs::path run_test_dir() {
  return orthosonar::replay::testing::case_dir("run_api", Catch::getResultCapture().getCurrentTestName());
}

// A short reduced-resolution harbor mission, simulated once per test process.
const std::string& fixture() {
  static const std::string path = [] {
    const fs::path p = run_test_dir() / "harbor_12s.mcap";
    run::MissionSpec spec;
    spec.scene = "harbor";
    spec.duration_s = 12.0;
    spec.resolution = sim::Resolution::kReduced;
    spec.seed = 3;
    spec.render_threads = 1;
    auto made = run::ensure_mission_fixture(spec, p.string());
    REQUIRE(made.ok());
    return p.string();
  }();
  return path;
}

}  // namespace

TEST_CASE("run_fixture gives one digest for 1 2 4 and 8 threads and over repeated runs", "[run]") {
  std::string first;
  for (int threads : {1, 1, 2, 4, 8, 2}) {
    run::RunOptions o;
    o.threads_override = threads;
    auto r = run::run_fixture(fixture(), o);
    REQUIRE(r.ok());
    CHECK(r->config.threads == threads);
    REQUIRE(r->counts.pairs > 0);
    REQUIRE(r->digest.overall_hex.size() == 64);
    if (first.empty()) first = r->digest.overall_hex;
    CHECK(r->digest.overall_hex == first);
  }
}

TEST_CASE("run_fixture reports progress and stops when cancelled", "[run]") {
  run::RunOptions o;
  std::vector<run::Progress> seen;
  run::RunControl control;
  control.progress_every = 500;
  control.progress = [&](const run::Progress& p) { seen.push_back(p); };
  auto full = run::run_fixture(fixture(), o, control);
  REQUIRE(full.ok());
  REQUIRE(seen.size() >= 3);
  for (size_t i = 1; i < seen.size(); ++i) {
    CHECK(seen[i].events >= seen[i - 1].events);
    CHECK(seen[i].fraction >= seen[i - 1].fraction);
  }
  CHECK(seen.back().fraction == Approx(1.0).margin(0.05));
  CHECK(seen.back().events == full->counts.events);

  // Cancel from the progress callback after the first report: the run stops with an Error
  // that says so, and never reaches the end of the recording.
  std::atomic<bool> cancel{false};
  int64_t reported = 0;
  run::RunControl stop;
  stop.cancel = &cancel;
  stop.progress_every = 500;
  stop.progress = [&](const run::Progress& p) {
    reported = p.events;
    cancel = true;
  };
  auto cancelled = run::run_fixture(fixture(), o, stop);
  REQUIRE_FALSE(cancelled.ok());
  CHECK(run::is_cancelled(cancelled.error()));
  CHECK(cancelled.error().message.find("500 events") != std::string::npos);
  CHECK(reported == 500);
}

TEST_CASE("an exception in a fusion task on a worker thread becomes an Error", "[run]") {
  auto src = replay::FixtureSource::open(fixture());
  REQUIRE(src.ok());
  run::RunOptions o;
  auto config = run::effective_config((*src)->metadata(), o);
  REQUIRE(config.ok());
  o.config = *config;
  o.config.threads = 4;
  std::atomic<int> calls{0};
  const mapping::FuseFn failing = [&](const SonarPing& h, const SonarPing& v) {
    if (++calls == 5) throw std::runtime_error("injected fusion fault");
    return perception::fuse_pair(h, v, o.config.pipeline.fusion);
  };
  auto r = run::run_source(**src, (*src)->metadata(), o, std::nullopt, {}, failing);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("injected fusion fault") != std::string::npos);
  CHECK(r.error().message.find("fixture:") != std::string::npos);  // names the source
}

TEST_CASE("configuration precedence: defaults < fixture < config file < flags", "[run]") {
  const run::RunConfig defaults;
  const std::map<std::string, std::string> metadata = {{"T_V_h", "0.5 0.1 0 0 0 0.25"}};
  run::RunOptions o;
  run::ConfigSources sources;
  auto from_fixture = run::effective_config(metadata, o, &sources);
  REQUIRE(from_fixture.ok());
  CHECK(from_fixture->pipeline.fusion.T_V_h.translation().x() == Approx(0.5));
  CHECK(from_fixture->pipeline.fusion.T_V_v.isApprox(defaults.pipeline.fusion.T_V_v));
  CHECK(sources.at("fusion.T_V_h") == "fixture");
  CHECK(sources.count("fusion.T_V_v") == 0);

  o.config_yaml = "fusion: {T_V_h: \"0.7 0 0 0 0 0\"}\nthreads: 3\n";
  o.config_origin = "c.yaml";
  auto from_yaml = run::effective_config(metadata, o, &sources);
  REQUIRE(from_yaml.ok());
  CHECK(from_yaml->pipeline.fusion.T_V_h.translation().x() == Approx(0.7));
  CHECK(from_yaml->threads == 3);
  CHECK(sources.at("fusion.T_V_h") == "config:c.yaml");

  o.threads_override = 2;
  auto from_flags = run::effective_config(metadata, o, &sources);
  REQUIRE(from_flags.ok());
  CHECK(from_flags->threads == 2);
  CHECK(sources.at("threads") == "command line");

  const std::map<std::string, std::string> bad = {{"T_V_v", "0 0 nan 0 0 0"}};
  auto rejected = run::effective_config(bad, run::RunOptions{});
  REQUIRE_FALSE(rejected.ok());
  CHECK(rejected.error().message.find("T_V_v") != std::string::npos);
}

TEST_CASE("replay maps with the fixture's recorded extrinsics", "[run]") {
  // The same recording labelled with other extrinsics maps differently: the run honours
  // the metadata, and a --config naming the default extrinsics restores the original.
  auto src = replay::FixtureSource::open(fixture());
  REQUIRE(src.ok());
  auto meta = (*src)->metadata();
  run::RunOptions o;
  auto recorded = run::effective_config(meta, o);
  REQUIRE(recorded.ok());
  meta["T_V_h"] = "0.35 0 0.3 0 0 0.05";
  auto other = run::effective_config(meta, o);
  REQUIRE(other.ok());
  CHECK_FALSE(other->pipeline.fusion.T_V_h.isApprox(recorded->pipeline.fusion.T_V_h));
  o.config_yaml = "fusion: {T_V_h: \"0.35 0 0 0 0 0\"}";
  auto overridden = run::effective_config(meta, o);
  REQUIRE(overridden.ok());
  CHECK(overridden->pipeline.fusion.T_V_h.translation().z() == Approx(0.0));
}

TEST_CASE("every configuration key rejects a value outside its range, naming the key", "[run]") {
  const auto ranges = run::config_key_ranges();
  // Every key config_to_json prints has a range (no key escapes the checks).
  std::set<std::string> printed;
  std::function<void(const nlohmann::json&, const std::string&)> flatten = [&](const nlohmann::json& j,
                                                                              const std::string& prefix) {
    if (j.is_object()) {
      for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k);
      return;
    }
    printed.insert(prefix);
  };
  flatten(run::config_to_json(run::RunConfig{}), "");
  std::set<std::string> checked;
  for (const auto& r : ranges) checked.insert(r.key);
  CHECK(printed == checked);
  REQUIRE(ranges.size() >= 40);

  for (const auto& r : ranges) {
    // "a.b.c: bad" as nested YAML maps.
    std::string yaml, indent;
    size_t start = 0;
    for (size_t dot = r.key.find('.'); dot != std::string::npos; dot = r.key.find('.', start)) {
      yaml += indent + r.key.substr(start, dot - start) + ":\n";
      indent += "  ";
      start = dot + 1;
    }
    yaml += indent + r.key.substr(start) + ": " + r.bad_value + "\n";
    run::RunConfig c;
    const Status s = run::apply_config_yaml(yaml, c);
    INFO(r.key << " = " << r.bad_value << " (valid: " << r.range << ")");
    REQUIRE_FALSE(s.ok());
    CHECK(s.error().message.find("'" + r.key + "'") != std::string::npos);
  }
  // NaN and infinity are never accepted by a real-valued key.
  run::RunConfig c;
  CHECK_FALSE(run::apply_config_yaml("slam: {voxel_m: .nan}", c).ok());
  CHECK_FALSE(run::apply_config_yaml("slam: {kf_distance_m: .inf}", c).ok());
  CHECK_FALSE(run::apply_config_yaml("mapping: {fusion_batch_pairs: -1}", c).ok());
  // The documented defaults are inside their ranges.
  CHECK(run::apply_config_yaml("slam: {voxel_m: 0.5, icp: {trim_fraction: 0.8}}\nthreads: 1", c).ok());
}

TEST_CASE("a mission fixture made with another navigation profile than the default is simulated again, not reused", "[run]") {
  const fs::path p = run_test_dir() / "harbor_4s_profiles.mcap";
  fs::remove(p);
  run::MissionSpec spec;
  spec.scene = "harbor";
  spec.duration_s = 4.0;
  spec.resolution = sim::Resolution::kReduced;
  spec.render_threads = 1;
  run::MissionSpec ahrs = spec;
  ahrs.sim_config_yaml = "nav_profile: ahrs\n";
  auto made = run::ensure_mission_fixture(ahrs, p.string());
  REQUIRE(made.ok());
  CHECK(*made);
  // The default mission (the paper's vehicle) at the same path: the ahrs fixture is not it.
  made = run::ensure_mission_fixture(spec, p.string());
  REQUIRE(made.ok());
  CHECK(*made);
  auto fixture = replay::FixtureSource::open(p.string());
  REQUIRE(fixture.ok());
  CHECK((*fixture)->metadata().at("nav_profile") == "paper");
  // Now it is: reused.
  made = run::ensure_mission_fixture(spec, p.string());
  REQUIRE(made.ok());
  CHECK_FALSE(*made);
}
