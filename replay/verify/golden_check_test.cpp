// Checking and updating one golden run without rendering: the bounds verdict, image checks
// that fail rather than pass without a display or stored images, and --update with
// --no-images (the stored images kept, a violated bound reported).
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

#include "replay/verify/golden_check.hpp"
#include "replay/verify/testing.hpp"
#include "reports/test_dir.hpp"

namespace orthosonar::verify {
namespace {

namespace fs = std::filesystem;

// golden/scenarios/demo.yaml and golden/bounds.yaml under a fresh test directory.
fs::path layout(const std::string& name, const std::string& bounds) {
  const fs::path root = reports::testing::test_dir(name);
  fs::create_directories(root / "scenarios");
  std::ofstream(root / "scenarios" / "demo.yaml") << testing::kDemoScenario << R"(expected:
  digest: abc
  outputs: {fusion/map: "111"}
  metrics: {keyframes: 12}
  images: {fusion: demo/fusion_top.png}
)";
  std::ofstream(root / "bounds.yaml") << bounds;
  return root / "scenarios" / "demo.yaml";
}

const char* const kCheckBounds = testing::kDemoBounds;

run::RunOutput check_output(double coverage) {
  return testing::demo_run_output(static_cast<int64_t>(coverage));
}

TEST_CASE("golden check: expectations and bounds hold, images skipped", "[golden]") {
  auto s = load_scenario(layout("golden_check_ok", kCheckBounds).string());
  REQUIRE(s.ok());
  std::ostringstream out;
  CheckOptions o;
  o.images = false;
  CHECK(check_run(*s, check_output(900), o, Status::Ok(), out));
  CHECK(out.str().find("bound ok   fusion.coverage_voxels") != std::string::npos);
  std::ostringstream low;
  CHECK_FALSE(check_run(*s, check_output(400), o, Status::Ok(), low));  // below the coverage floor
  CHECK(low.str().find("bound FAIL fusion.coverage_voxels") != std::string::npos);
}

TEST_CASE("golden check: missing bounds fail, never pass", "[golden][bounds]") {
  auto s = load_scenario(layout("golden_check_no_bounds", "scenarios:\n  other: {}\n").string());
  REQUIRE(s.ok());
  std::ostringstream out;
  CHECK_FALSE(bounds_hold(*s, check_output(900), "", out));
  CHECK(out.str().find("no absolute bounds for scenario demo") != std::string::npos);
  std::ostringstream missing;
  CHECK_FALSE(bounds_hold(*s, check_output(900), "/nonexistent/bounds.yaml", missing));
  CHECK(missing.str().find("bounds FAILED: /nonexistent/bounds.yaml") != std::string::npos);
}

TEST_CASE("golden check: without a display or stored images the image check fails", "[golden]") {
  const auto path = layout("golden_check_images", kCheckBounds);
  auto s = load_scenario(path.string());
  REQUIRE(s.ok());
  std::ostringstream no_display;
  CHECK_FALSE(images_match(*s, check_output(900), path.parent_path() / "run", Error{"no X display"}, no_display));
  CHECK(no_display.str().find("image check FAILED for scenario demo: no X display") != std::string::npos);
  Scenario bare = *s;
  bare.expected->images.reset();
  std::ostringstream no_images;
  CHECK_FALSE(images_match(bare, check_output(900), path.parent_path() / "run", Status::Ok(), no_images));
  CHECK(no_images.str().find("no image expectations recorded") != std::string::npos);
}

TEST_CASE("golden update --no-images keeps the stored images and reports a violated bound", "[golden][bounds]") {
  const auto path = layout("golden_update", kCheckBounds);
  auto s = load_scenario(path.string());
  REQUIRE(s.ok());
  run::RunOutput run = check_output(400);  // violates the coverage floor
  run.digest.overall_hex = "abd";
  std::ostringstream out;
  auto ok = update_scenario(*s, run, false, path.parent_path() / "out", "", out);
  REQUIRE(ok.ok());
  CHECK_FALSE(*ok);
  const std::string o = out.str();
  CHECK(o.find("demo: digest abc -> abd  (CHANGED)") == 0);
  CHECK(o.find("images kept as stored (--no-images)") != std::string::npos);
  CHECK(o.find("violates the absolute bounds") != std::string::npos);
  auto back = load_scenario(path.string());
  REQUIRE(back.ok());
  CHECK(back->expected->digest == std::optional<std::string>("abd"));
  CHECK(back->expected->images->at("fusion") == "demo/fusion_top.png");
  std::ostringstream again;
  auto ok2 = update_scenario(*back, check_output(900), false, path.parent_path() / "out", "", again);
  REQUIRE(ok2.ok());
  CHECK(*ok2);
}

}  // namespace
}  // namespace orthosonar::verify
