// Absolute bounds of golden scenarios (golden/bounds.yaml): the file's errors name the key,
// and every check passes, fails or is a known failure as the bounds say.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>

#include "replay/verify/golden_bounds.hpp"
#include "replay/verify/testing.hpp"
#include "reports/test_dir.hpp"

namespace orthosonar::verify {
namespace {

std::string bounds_file(const std::string& name, const std::string& text) {
  const auto path = (reports::testing::test_dir(name) / "bounds.yaml").string();
  std::ofstream(path) << text;
  return path;
}

using testing::kDemoBounds;

std::map<std::string, double> good_metrics() {
  return {{"ate_slam_m", 0.5}, {"ate_dr_m", 1.0}, {"fusion.mae_m", 0.05}, {"fusion.rmse_m", 0.1},
          {"fusion.coverage_voxels", 900}};
}

TEST_CASE("golden bounds: a run within every bound passes", "[golden][bounds]") {
  auto all = load_golden_bounds(bounds_file("bounds_ok", kDemoBounds));
  REQUIRE(all.ok());
  const auto v = check_golden_bounds(all->at("demo"), good_metrics(), {"fusion"});
  CHECK(v.ok);
  CHECK(v.lines.size() == 6);
  for (const auto& l : v.lines) CHECK(l.rfind("ok   ", 0) == 0);
}

TEST_CASE("golden bounds: a violated, missing or unbounded value fails", "[golden][bounds]") {
  auto all = load_golden_bounds(bounds_file("bounds_fail", kDemoBounds));
  REQUIRE(all.ok());
  const auto& b = all->at("demo");
  auto m = good_metrics();
  m["fusion.coverage_voxels"] = 400;  // below the floor
  auto v = check_golden_bounds(b, m, {"fusion"});
  CHECK_FALSE(v.ok);
  CHECK(std::count_if(v.lines.begin(), v.lines.end(), [](const auto& l) { return l.rfind("FAIL fusion.coverage", 0) == 0; }) == 1);
  m = good_metrics();
  m.erase("fusion.mae_m");
  CHECK_FALSE(check_golden_bounds(b, m, {"fusion"}).ok);
  CHECK_FALSE(check_golden_bounds(b, good_metrics(), {"fusion", "submap"}).ok);  // no bounds for submap
  m = good_metrics();
  m["ate_slam_m"] = 0.9;  // <= 1.0 m but 0.9 > 0.8 x DR
  CHECK_FALSE(check_golden_bounds(b, m, {"fusion"}).ok);
}

TEST_CASE("golden bounds: expected failure is reported, its unexpected pass fails", "[golden][bounds]") {
  const std::string text = std::string(kDemoBounds).replace(std::string(kDemoBounds).find("    systems:"), 0,
                                                        "    expected_failure: {slam_worse_than_dr: known drift}\n");
  auto all = load_golden_bounds(bounds_file("bounds_xfail", text));
  REQUIRE(all.ok());
  const auto& b = all->at("demo");
  auto pass = check_golden_bounds(b, good_metrics(), {"fusion"});  // SLAM better than DR: unexpected pass
  CHECK_FALSE(pass.ok);
  auto m = good_metrics();
  m["ate_dr_m"] = 0.4;
  GoldenScenarioBounds relaxed = b;
  relaxed.ate_slam_over_dr_max = 2.0;
  auto known = check_golden_bounds(relaxed, m, {"fusion"});
  CHECK(known.ok);
  CHECK(std::count_if(known.lines.begin(), known.lines.end(),
                      [](const auto& l) { return l.rfind("KNOWN FAILURE", 0) == 0; }) == 1);
}

TEST_CASE("golden bounds: bad files are errors naming the key", "[golden][bounds]") {
  auto unknown = load_golden_bounds(bounds_file("bounds_unknown", "scenarios:\n  demo:\n    ate_max: 1\n"));
  REQUIRE_FALSE(unknown.ok());
  CHECK(unknown.error().message.find("scenarios.demo: unknown key 'ate_max'") != std::string::npos);
  auto negative = load_golden_bounds(bounds_file("bounds_negative", "scenarios:\n  demo:\n    ate_slam_max_m: -1\n"));
  REQUIRE_FALSE(negative.ok());
  CHECK(negative.error().message.find("ate_slam_max_m: must be a finite number >= 0") != std::string::npos);
  CHECK_FALSE(load_golden_bounds("/nonexistent/bounds.yaml").ok());
  CHECK(default_golden_bounds_path("golden/scenarios/harbor.yaml") == "golden/bounds.yaml");
}

}  // namespace
}  // namespace orthosonar::verify
