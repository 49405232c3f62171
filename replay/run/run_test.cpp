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
#include <optional>
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

// A short reduced-resolution harbor mission, rendered on one thread.
run::MissionSpec short_harbor(double duration_s) {
  run::MissionSpec spec;
  spec.scene = "harbor";
  spec.duration_s = duration_s;
  spec.resolution = sim::Resolution::kReduced;
  spec.render_threads = 1;
  return spec;
}

// One of them, simulated once per test process.
const std::string& fixture() {
  static const std::string path = [] {
    const fs::path p = run_test_dir() / "harbor_12s.mcap";
    run::MissionSpec spec = short_harbor(12.0);
    spec.seed = 3;
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
  const run::MissionSpec spec = short_harbor(4.0);
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

TEST_CASE("a mission's route is in its fixture, and a fixture flown on another route is not reused", "[run]") {
  const fs::path p = run_test_dir() / "harbor_4s_routes.mcap";
  fs::remove(p);
  const run::MissionSpec spec = short_harbor(4.0);
  auto made = run::ensure_mission_fixture(spec, p.string());
  REQUIRE(made.ok());
  {
    auto f = replay::FixtureSource::open(p.string());
    REQUIRE(f.ok());
    CHECK((*f)->metadata().count("route") == 0);  // the scene's own route says nothing
  }
  run::MissionSpec survey = spec;
  survey.route = "survey";
  made = run::ensure_mission_fixture(survey, p.string());
  REQUIRE(made.ok());
  CHECK(*made);  // simulated again: the default route's fixture is another mission
  {
    auto f = replay::FixtureSource::open(p.string());
    REQUIRE(f.ok());
    CHECK((*f)->metadata().at("route") == "survey");
  }
  made = run::ensure_mission_fixture(survey, p.string());
  REQUIRE(made.ok());
  CHECK_FALSE(*made);  // reused
  run::MissionSpec unknown = spec;
  unknown.route = "scenic";
  made = run::ensure_mission_fixture(unknown, (run_test_dir() / "unknown_route.mcap").string());
  REQUIRE_FALSE(made.ok());
  CHECK(made.error().message.find("scenic") != std::string::npos);
  CHECK(made.error().message.find("survey") != std::string::npos);  // names the routes there are
}

TEST_CASE("the ping pair kept is the one with the most fused points, the same for any thread count", "[run]") {
  // The survey route: structure ahead within seconds (the default route's first 12 s fuse nothing).
  const std::string path = (run_test_dir() / "harbor_survey_12s.mcap").string();
  run::MissionSpec spec = short_harbor(12.0);
  spec.route = "survey";
  REQUIRE(run::ensure_mission_fixture(spec, path).ok());
  std::optional<run::PingPairView> first;
  for (int threads : {1, 2}) {
    run::RunOptions o;
    o.threads_override = threads;
    auto r = run::run_fixture(path, o);
    REQUIRE(r.ok());
    REQUIRE(r->ping_pair);
    REQUIRE_FALSE(r->ping_pair->fused.points.empty());
    if (!first) {
      first = r->ping_pair;
      continue;
    }
    CHECK(r->ping_pair->h == first->h);
    CHECK(r->ping_pair->v == first->v);
    CHECK(r->ping_pair->fused.points.size() == first->fused.points.size());
  }
  // The most: every pair's fused count, seen through the pipeline's observer, is at most the kept one's.
  run::RunOptions o;
  auto opened = replay::FixtureSource::open(path);
  REQUIRE(opened.ok());
  auto eff = run::effective_config((*opened)->metadata(), o, nullptr, (*opened)->attachments());
  REQUIRE(eff.ok());
  mapping::Pipeline pipeline(eff->pipeline);
  size_t most = 0, pairs = 0;
  pipeline.set_pair_observer([&](const SonarPing&, const SonarPing&, const perception::FusionResult& f) {
    most = std::max(most, f.points.size());
    ++pairs;
  });
  while (true) {
    hal::Pulled p = (*opened)->next();
    REQUIRE_FALSE(p.error);
    if (p.end_of_stream || !p.event) break;
    pipeline.consume(*p.event);
  }
  pipeline.finish();
  CHECK(pairs == static_cast<size_t>(pipeline.counts().pairs));
  CHECK(most == first->fused.points.size());
}
