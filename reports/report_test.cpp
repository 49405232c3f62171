#include "reports/report.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "reports/render.hpp"
#include "reports/synthetic_run.hpp"
#include "reports/test_dir.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;
namespace fs = std::filesystem;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
}  // namespace

TEST_CASE("the report references only files that exist and shows every part", "[report]") {
  const Status display = check_display();
  if (!display) FAIL(display.error().message);
  const auto dir = testing::test_dir("report_full");
  REQUIRE(write_synthetic_run((dir / "run").string(), {.points_per_piling = 40}).ok());
  REQUIRE(write_synthetic_run((dir / "golden").string(), {.points_per_piling = 40, .drop_fraction = 0.3}).ok());
  ReportOptions o;
  o.golden_dir = (dir / "golden").string();
  o.width_px = 640;
  o.height_px = 480;
  const Status s = write_report((dir / "run").string(), (dir / "report").string(), o);
  REQUIRE(s.ok());
  const std::string html = slurp(dir / "report" / "report.html");
  const auto files = referenced_files(html);
  // 3 systems x 2 views, trajectories, 2 heat maps, 3 x (2 comparisons + 2 difference views).
  CHECK(files.size() == 6 + 1 + 2 + 12);
  for (const auto& f : files) {
    INFO(f);
    CHECK(fs::exists(dir / "report" / f));
    CHECK(fs::file_size(dir / "report" / f) > 1000);
  }
  const std::vector<std::string> needles = {"Metrics", "Runtime", "slam_update", "synthetic_pilings",
                                            "software version: synthetic", std::string(64, 'f'),
                                            "Comparison with golden", "heatmap_coverage.png", "fixture.counts.sonar_h",
                                            "configuration used (2 values)", "config.fusion.cfar_pfa"};
  for (const auto& needle : needles)
    CHECK(html.find(needle) != std::string::npos);
  CHECK(html.find("<script") == std::string::npos);
  CHECK(html.find("<style>") != std::string::npos);
}

TEST_CASE("a run compared with itself scores zero image difference", "[report]") {
  const Status display = check_display();
  if (!display) FAIL(display.error().message);
  const auto dir = testing::test_dir("report_self");
  REQUIRE(write_synthetic_run((dir / "run").string(), {.points_per_piling = 20, .with_grid = false}).ok());
  ReportOptions o;
  o.golden_dir = (dir / "run").string();
  o.width_px = 320;
  o.height_px = 240;
  REQUIRE(write_report((dir / "run").string(), (dir / "report").string(), o).ok());
  const std::string html = slurp(dir / "report" / "report.html");
  CHECK(html.find("<td>fusion</td><td>top</td><td>0.0000</td>") != std::string::npos);
  CHECK(html.find("<td>inference</td><td>oblique</td><td>0.0000</td>") != std::string::npos);
}

TEST_CASE("the report of the same run is byte-identical HTML", "[report]") {
  const auto dir = testing::test_dir("report_deterministic");
  REQUIRE(write_synthetic_run((dir / "run").string(), {.points_per_piling = 20}).ok());
  ReportOptions o;
  o.require_renders = false;  // this property is about the HTML, not the renders
  const char* saved = std::getenv("DISPLAY");
  const std::string keep = saved ? saved : "";
  unsetenv("DISPLAY");
  const bool ok1 = write_report((dir / "run").string(), (dir / "r1").string(), o).ok();
  const bool ok2 = write_report((dir / "run").string(), (dir / "r2").string(), o).ok();
  o.require_renders = true;
  const Status s = write_report((dir / "run").string(), (dir / "r3").string(), o);
  if (saved) setenv("DISPLAY", keep.c_str(), 1);  // restored before any REQUIRE can leave
  REQUIRE(ok1);
  REQUIRE(ok2);
  const std::string a = slurp(dir / "r1" / "report.html");
  CHECK(a == slurp(dir / "r2" / "report.html"));
  CHECK(a.find("3D renders skipped") != std::string::npos);
  for (const auto& f : referenced_files(a)) CHECK(fs::exists(dir / "r1" / f));
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find("xvfb-run") != std::string::npos);
}

TEST_CASE("referenced files skips URLs and fragments", "[report]") {
  const std::string html = R"(<img src="a.png"><a href="#x">x</a><a href="https://e.org/">e</a><img src="a.png">)"
                           R"(<img src="sub/b.png"><a href="/abs">a</a>)";
  CHECK(referenced_files(html) == std::vector<std::string>{"a.png", "sub/b.png"});
}

TEST_CASE("a report of a missing directory fails naming it", "[report]") {
  const auto dir = testing::test_dir("report_missing");
  const Status s = write_report((dir / "nope").string(), (dir / "out").string(), {});
  REQUIRE_FALSE(s.ok());
  CHECK(s.error().message.find("nope") != std::string::npos);
}
