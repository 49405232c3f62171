#include "hal/codec/image_codec.hpp"
#include "reports/render.hpp"

#include <catch2/catch.hpp>

#include "reports/image_compare.hpp"
#include "reports/map_views.hpp"
#include "reports/synthetic_run.hpp"
#include "reports/test_dir.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

namespace {
// Renders need an X display; say so plainly instead of letting VTK abort.
void require_display() {
  const Status s = check_display();
  if (!s) FAIL(s.error().message);
}
}  // namespace

TEST_CASE("map renders are 1280x960 and not blank for both views", "[report]") {
  require_display();
  const auto dir = testing::test_dir("render_views");
  REQUIRE(write_synthetic_run((dir / "run").string(), {.points_per_piling = 60}).ok());
  auto run = load_run((dir / "run").string());
  REQUIRE(run.ok());
  const Bounds b = run_bounds(*run);
  const auto& map = run->systems[1].map_W;
  for (View v : {View::kTop, View::kOblique}) {
    auto img = render_map_view(*run, map, v, b, std::string("synthetic ") + view_name(v));
    REQUIRE(img.ok());
    CHECK(img->cols == 1280);
    CHECK(img->rows == 960);
    CHECK(pixel_variance(*img) > 50.0);
    CHECK(codec::write_png((dir / (std::string("map_") + view_name(v) + ".png")).string(), *img).ok());
    // The map changes the picture: the same view without points differs clearly.
    auto empty = render_map_view(*run, {}, v, b, std::string("synthetic ") + view_name(v));
    REQUIRE(empty.ok());
    CHECK(image_difference(*img, *empty) > 0.003);
  }
}

TEST_CASE("renders are stable across two runs and detect a shifted map", "[report]") {
  require_display();
  const auto dir = testing::test_dir("render_stable");
  REQUIRE(write_synthetic_run((dir / "a").string(), {.points_per_piling = 60}).ok());
  REQUIRE(write_synthetic_run((dir / "b").string(), {.points_per_piling = 60, .map_shift_m = 1.0}).ok());
  auto a = load_run((dir / "a").string());
  auto b = load_run((dir / "b").string());
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  const Bounds bounds = run_bounds(*a);
  RenderConfig small;
  small.width_px = 640;
  small.height_px = 480;
  auto first = render_map_view(*a, a->systems[0].map_W, View::kOblique, bounds, "run", small);
  auto second = render_map_view(*a, a->systems[0].map_W, View::kOblique, bounds, "run", small);
  auto shifted = render_map_view(*a, b->systems[0].map_W, View::kOblique, bounds, "run", small);
  REQUIRE(first.ok());
  REQUIRE(second.ok());
  REQUIRE(shifted.ok());
  const double same = image_difference(*first, *second);
  const double moved = image_difference(*first, *shifted);
  INFO("difference of two renders " << same << ", of a map shifted by 1 m " << moved);
  CHECK(same < 0.0005);
  CHECK(moved > 5.0 * same);
  CHECK(moved > 0.001);
}

TEST_CASE("a render without a display is an error, not a crash", "[report]") {
  const char* saved = std::getenv("DISPLAY");
  const std::string keep = saved ? saved : "";
  unsetenv("DISPLAY");
  RenderScene scene;
  scene.points_W = {{0, 0, 0}, {1, 1, 1}};
  Bounds b;
  b.extend({0, 0, 0});
  b.extend({1, 1, 1});
  auto r = render_scene(scene, fixed_camera(b, View::kTop, 4.0 / 3.0));
  if (saved) setenv("DISPLAY", keep.c_str(), 1);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("xvfb-run") != std::string::npos);
}
