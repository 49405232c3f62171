// Golden scenario files without running a mission: loading (errors name the file),
// comparing a run's digest, outputs and metrics with the expectations, and the round trip
// through write_expectations.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "replay/verify/golden_scenario.hpp"
#include "replay/verify/testing.hpp"
#include "reports/test_dir.hpp"

namespace orthosonar::verify {
namespace {

using testing::kDemoScenario;

std::string write_file(const std::string& dir, const std::string& text) {
  const auto path = (reports::testing::test_dir(dir) / "demo.yaml").string();
  std::ofstream(path) << text;
  return path;
}

run::RunOutput scenario_output() { return testing::demo_run_output(); }

TEST_CASE("golden scenario: load reads settings, no expectations before --update", "[golden]") {
  auto s = load_scenario(write_file("golden_load", kDemoScenario));
  REQUIRE(s.ok());
  CHECK(s->name == "demo");
  CHECK(s->seed == 3);
  CHECK(s->systems == std::vector<std::string>{"fusion"});
  CHECK(s->tol.ate_abs_m == 0.004);
  CHECK(s->tol.image_difference == kDefaultImageDifference);
  CHECK_FALSE(s->expected.has_value());
  std::ostringstream out;
  CHECK_FALSE(expectations_match(*s, scenario_output(), out));
  CHECK(out.str().find("no expectations recorded") != std::string::npos);
}

TEST_CASE("golden scenario: bad files are errors naming the file", "[golden]") {
  std::string bad = kDemoScenario;
  bad.replace(bad.find("name: demo"), 10, "name: a/b");
  const auto path = write_file("golden_bad_name", bad);
  auto s = load_scenario(path);
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find(path) == 0);
  CHECK(s.error().message.find("plain file name") != std::string::npos);
  std::string no_seed = kDemoScenario;
  no_seed.erase(no_seed.find("seed: 3"), 8);
  auto s2 = load_scenario(write_file("golden_no_seed", no_seed));
  REQUIRE_FALSE(s2.ok());
  CHECK(s2.error().message.find("demo.yaml") != std::string::npos);
}

TEST_CASE("golden scenario: metric tolerances by kind, counts exact", "[golden]") {
  const Tolerances t{0.01, 0.002, 0.003, 0.004};
  CHECK(tolerance_for("fusion.coverage_voxels", -2000, t) == Approx(20.0));
  CHECK(tolerance_for("fusion.mae_m", 1, t) == 0.002);
  CHECK(tolerance_for("submap.rmse_m", 1, t) == 0.003);
  CHECK(tolerance_for("ate_slam_m", 1, t) == 0.004);
  CHECK(tolerance_for("keyframes", 12, t) == 0.0);
  const auto m = scenario_metrics(scenario_output());
  CHECK(m.at("fusion.coverage_voxels") == 1000);
  CHECK(m.at("ate_slam_m") == 0.75);
  CHECK(m.at("loop_closures") == 2);
  CHECK(m.size() == 7);
}

TEST_CASE("golden scenario: written expectations match the run, changes are named", "[golden]") {
  const auto path = write_file("golden_roundtrip", kDemoScenario);
  auto s = load_scenario(path);
  REQUIRE(s.ok());
  const run::RunOutput run = scenario_output();
  REQUIRE(write_expectations(*s, run, {{"fusion", "demo/fusion_top.png"}}).ok());
  auto back = load_scenario(path);
  REQUIRE(back.ok());
  REQUIRE(back->expected.has_value());
  CHECK(back->expected->digest == std::optional<std::string>("abc"));
  CHECK(back->expected->outputs == run.digest.outputs);
  CHECK(back->expected->metrics == scenario_metrics(run));
  REQUIRE(back->expected->images.has_value());
  CHECK(back->expected->images->at("fusion") == "demo/fusion_top.png");
  std::ostringstream same;
  CHECK(expectations_match(*back, run, same));
  CHECK(same.str().empty());

  run::RunOutput changed = scenario_output();
  changed.digest.overall_hex = "abd";
  changed.digest.outputs.erase("fusion/traj");
  changed.digest.outputs["fusion/map"] = "999";
  changed.digest.outputs["fusion/new"] = "333";
  changed.systems[0].accuracy->mae_m = 0.0515;   // within 0.002
  changed.systems[0].accuracy->rmse_m = 0.0735;  // beyond 0.003
  changed.counts.keyframes = 13;                 // counts are exact
  std::ostringstream diff;
  CHECK_FALSE(expectations_match(*back, changed, diff));
  const std::string d = diff.str();
  CHECK(d.find("digest differs: expected abc, got abd") != std::string::npos);
  CHECK(d.find("output differs: fusion/map") != std::string::npos);
  CHECK(d.find("new output fusion/new") != std::string::npos);
  CHECK(d.find("missing output fusion/traj") != std::string::npos);
  CHECK(d.find("out of tolerance: fusion.rmse_m") != std::string::npos);
  CHECK(d.find("out of tolerance: keyframes") != std::string::npos);
  CHECK(d.find("fusion.mae_m") == std::string::npos);
}

}  // namespace
}  // namespace orthosonar::verify
