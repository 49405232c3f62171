#include "reports/report.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <openssl/evp.h>

#include "hal/codec/image_codec.hpp"
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

// Every src="..." / href="..." value of the HTML, in order.
std::vector<std::string> link_values(const std::string& html) {
  std::vector<std::string> out;
  for (const std::string key : {"src=\"", "href=\""}) {
    for (size_t pos = html.find(key); pos != std::string::npos; pos = html.find(key, pos + 1)) {
      const size_t b = pos + key.size();
      out.push_back(html.substr(b, html.find('"', b) - b));
    }
  }
  return out;
}

// data-file="..." values: the PNG beside the report each embedded image also is.
std::vector<std::string> data_files(const std::string& html) {
  std::vector<std::string> out;
  const std::string key = "data-file=\"";
  for (size_t pos = html.find(key); pos != std::string::npos; pos = html.find(key, pos + 1)) {
    const size_t b = pos + key.size();
    out.push_back(html.substr(b, html.find('"', b) - b));
  }
  return out;
}

std::vector<uint8_t> from_base64(const std::string& text) {
  std::vector<uint8_t> out(text.size() / 4 * 3 + 3);
  const int n = EVP_DecodeBlock(out.data(), reinterpret_cast<const unsigned char*>(text.data()), static_cast<int>(text.size()));
  REQUIRE(n >= 0);
  out.resize(static_cast<size_t>(n));
  size_t pad = 0;  // EVP_DecodeBlock keeps the padding's zero bytes
  for (size_t i = text.size(); i > 0 && text[i - 1] == '=' && pad < 2; --i) ++pad;
  out.resize(out.size() - pad);
  return out;
}

TEST_CASE("the report is self-contained: every figure embedded, decodable and also written beside it", "[report]") {
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
  // No reference to a file or a URL: only data URIs.
  const auto links = link_values(html);
  for (const auto& v : links) {
    INFO(v.substr(0, 40));
    CHECK(v.rfind("data:image/", 0) == 0);
  }
  CHECK(referenced_files(html).empty());
  const auto files = data_files(html);
  // 3 systems x 2 views, 3 distance-to-mesh views, the ping pair, trajectories and their error
  // over time, 2 heat maps, 3 x (2 comparisons + 2 difference views).
  CHECK(files.size() == 6 + 3 + 1 + 2 + 2 + 12);
  REQUIRE(links.size() == files.size());
  for (size_t i = 0; i < files.size(); ++i) {
    INFO(files[i]);
    REQUIRE(fs::exists(dir / "report" / files[i]));
    CHECK(fs::file_size(dir / "report" / files[i]) > 1000);
    const std::string& uri = links[i];
    const bool png = uri.rfind("data:image/png;base64,", 0) == 0;
    const auto bytes = from_base64(uri.substr(uri.find(',') + 1));
    auto image = codec::decode_image(bytes, codec::DecodeAs::kBgr, files[i]);
    REQUIRE(image.ok());
    CHECK(image->cols > 100);
    if (png) {
      const std::string file = slurp(dir / "report" / files[i]);
      CHECK(bytes == std::vector<uint8_t>(file.begin(), file.end()));  // the same PNG
    }
  }
  for (const std::string name : {"error_fusion_top.png", "ping_pair.png", "trajectory_error.png"})
    CHECK(std::find(files.begin(), files.end(), name) != files.end());
  const std::vector<std::string> needles = {"Metrics", "Runtime", "slam_update", "synthetic_pilings",
                                            "software version: synthetic", std::string(64, 'f'),
                                            "Comparison with golden", "heatmap_coverage.png", "fixture.counts.sonar_h",
                                            "configuration used (2 values)", "config.fusion.cfar_pfa",
                                            "Where the map is wrong", "What the sonars saw"};
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
  CHECK(referenced_files(a).empty());
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
