#include "hal/codec/image_codec.hpp"
#include "reports/heatmap.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "reports/colormap.hpp"
#include "reports/draw_util.hpp"
#include "reports/test_dir.hpp"
#include "reports/trajectory_plot.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

namespace {
Grid paper_grid() {
  Grid g;
  g.scene = "marina1";
  for (const char* sys : {"submap", "fusion", "inference"})  // unordered on purpose
    for (double rot : {90.0, 30.0, 60.0})
      for (double dist : {5.0, 1.0, 3.0, 2.0, 4.0}) {
        GridCell c;
        c.system = sys;
        c.rotation_deg = rot;
        c.distance_m = dist;
        c.coverage_voxels = 1000.0 * dist + rot + (std::string(sys) == "submap" ? 20000.0 : 0.0);
        g.cells.push_back(c);
      }
  return g;
}
}  // namespace

TEST_CASE("heat map has the paper's layout: panels per system, rotations by distances", "[report]") {
  auto hm = draw_heatmap(paper_grid());
  REQUIRE(hm.ok());
  CHECK(hm->systems == std::vector<std::string>{"fusion", "submap", "inference"});
  CHECK(hm->rotations_deg == std::vector<double>{30.0, 60.0, 90.0});
  CHECK(hm->distances_m == std::vector<double>{1.0, 2.0, 3.0, 4.0, 5.0});
  REQUIRE(hm->cells.size() == 45);
  CHECK(hm->min_value == 1030.0);
  CHECK(hm->max_value == 25090.0);
  const cv::Rect canvas(0, 0, hm->image.cols, hm->image.rows);
  for (size_t i = 0; i < hm->cells.size(); ++i) {
    const auto& c = hm->cells[i];
    CHECK(c.has_value);
    CHECK((c.rect & canvas) == c.rect);
    // Rows go down with rotation, columns right with distance, panels right with system.
    const size_t panel = i / 15, row = (i % 15) / 5, col = i % 5;
    CHECK(c.system == hm->systems[panel]);
    CHECK(c.rotation_deg == hm->rotations_deg[row]);
    CHECK(c.distance_m == hm->distances_m[col]);
    CHECK(c.text == std::to_string(static_cast<int>(c.value)));
    if (col > 0) CHECK(c.rect.x > hm->cells[i - 1].rect.x);
    if (row > 0) CHECK(c.rect.y > hm->cells[i - 5].rect.y);
    // The cell's fill (a corner, away from the printed count) is the colour scale's colour.
    const cv::Vec3b px = hm->image.at<cv::Vec3b>(c.rect.y + 4, c.rect.x + 4);
    const cv::Scalar want = to_bgr(colour_at(ColourMap::kCoverage, (c.value - hm->min_value) / (hm->max_value - hm->min_value)));
    for (int k = 0; k < 3; ++k) CHECK(std::abs(px[k] - want[k]) <= 1.0);
  }
  CHECK(codec::write_png((testing::test_dir("heatmap") / "heatmap.png").string(), hm->image).ok());
}

TEST_CASE("missing heat map cells are grey and duplicates are an error", "[report]") {
  Grid g = paper_grid();
  g.cells.erase(g.cells.begin() + 3);
  auto hm = draw_heatmap(g);
  REQUIRE(hm.ok());
  CHECK(hm->cells.size() == 45);
  CHECK(std::count_if(hm->cells.begin(), hm->cells.end(), [](const HeatmapCell& c) { return !c.has_value; }) == 1);
  g.cells[0].coverage_voxels = std::numeric_limits<double>::quiet_NaN();  // null in grid.json
  auto hm2 = draw_heatmap(g);
  REQUIRE(hm2.ok());
  CHECK(std::count_if(hm2->cells.begin(), hm2->cells.end(), [](const HeatmapCell& c) { return c.text == "n/a"; }) == 1);
  CHECK(std::isfinite(hm2->min_value));
  g.cells.push_back(g.cells.front());
  CHECK_FALSE(draw_heatmap(g).ok());
  CHECK_FALSE(draw_heatmap(Grid{}).ok());
}

TEST_CASE("nice ticks are round numbers covering the range", "[report]") {
  CHECK(nice_ticks(0.0, 10.0, 5) == std::vector<double>{0, 2, 4, 6, 8, 10});
  CHECK(nice_ticks(-13.0, 13.0, 5) == std::vector<double>{-10, 0, 10});
  CHECK(nice_ticks(-13.0, 13.0, 6) == std::vector<double>{-10, -5, 0, 5, 10});
  CHECK(format_tick(0.25, 0.05) == "0.25");
  CHECK(format_tick(20.0, 5.0) == "20");
}

TEST_CASE("trajectory plot draws every series and refuses empty input", "[report]") {
  PlotSeries a{"truth", {{0, 0}, {10, 0}, {10, 5}}, {0.1, 0.1, 0.1}};
  PlotSeries b{"dr", {{0, 0}, {11, 1}, {12, 7}}, {1.0, 0.35, 0.2}};
  auto img = draw_trajectory_plot({a, b});
  REQUIRE(img.ok());
  CHECK(img->cols == 1280);
  CHECK(img->rows == 960);
  // The orange series is visible somewhere.
  int orange = 0;
  for (int y = 0; y < img->rows; ++y)
    for (int x = 0; x < img->cols; ++x) {
      const auto p = img->at<cv::Vec3b>(y, x);
      orange += (p[2] > 200 && p[1] < 140 && p[0] < 110) ? 1 : 0;
    }
  CHECK(orange > 200);
  CHECK_FALSE(draw_trajectory_plot({PlotSeries{"one", {{0, 0}}, {}}}).ok());
  CHECK(codec::write_png((testing::test_dir("trajectory_plot") / "trajectories.png").string(), *img).ok());
}
