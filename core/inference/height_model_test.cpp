#include "core/inference/height_model.hpp"

#include <algorithm>
#include <catch2/catch.hpp>

using namespace orthosonar::inference;

TEST_CASE("an unvisited cell is uniform and yields no MAP height", "[unit]") {
  HeightModel m;
  CHECK(m.bins() == 160);  // 8 m / 0.05 m
  const auto p = m.posterior(1.0, 2.0);
  CHECK(p.front() == Approx(1.0 / 160));
  CHECK(p.back() == Approx(1.0 / 160));
  const auto map = m.map_estimate(1.0, 2.0);
  CHECK_FALSE(map.below);
  CHECK_FALSE(map.above);
}

TEST_CASE("points at a known height concentrate the distribution there", "[unit]") {
  HeightModel m;
  for (int i = 0; i < 20; ++i) REQUIRE(m.update(0.51, 0.32, -1.23));
  const auto p = m.posterior(0.55, 0.38);  // same 0.1 m cell
  const auto best = static_cast<int>(std::max_element(p.begin(), p.end()) - p.begin());
  CHECK(std::abs(m.bin_center(best) - (-1.23)) <= 0.025 + 1e-9);
  CHECK(p[static_cast<size_t>(best)] > 0.7);
  const auto map = m.map_estimate(0.55, 0.38);
  REQUIRE(map.below);
  CHECK(map.below->z_m == Approx(m.bin_center(best)));
  CHECK_FALSE(map.above);  // the upper half has ~no mass
  // Other cells are untouched.
  CHECK_FALSE(m.visited(0.75, 0.38));
}

TEST_CASE("a single update is the normalised Gaussian likelihood", "[unit]") {
  HeightModelConfig cfg;
  HeightModel m(cfg);
  REQUIRE(m.update(0.0, 0.0, 0.5));
  const auto p = m.posterior(0.0, 0.0);
  double sum = 0.0, mean = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    sum += p[i];
    mean += p[i] * m.bin_center(static_cast<int>(i));
  }
  CHECK(sum == Approx(1.0));
  CHECK(mean == Approx(0.5).margin(1e-3));
  // Heights outside the bin range are ignored.
  CHECK_FALSE(m.update(0.0, 0.0, 2.5));
  CHECK_FALSE(m.update(0.0, 0.0, -6.5));
  CHECK(m.updates() == 1);
}

TEST_CASE("two-sided MAP reports both sides only when both pass the threshold", "[unit]") {
  // Two cells: one learns +1.0, one learns -2.0; a third gets a weak mixture.
  HeightModelConfig cfg;
  cfg.min_map_probability = 0.3;
  HeightModel m(cfg);
  for (int i = 0; i < 10; ++i) m.update(0.05, 0.05, 1.01);
  for (int i = 0; i < 10; ++i) m.update(1.05, 0.05, -1.99);
  const auto up = m.map_estimate(0.05, 0.05);
  REQUIRE(up.above);
  CHECK(up.above->z_m == Approx(1.025));
  CHECK_FALSE(up.below);
  const auto down = m.map_estimate(1.05, 0.05);
  REQUIRE(down.below);
  CHECK(down.below->z_m == Approx(-1.975));
  CHECK_FALSE(down.above);
  // A loose threshold keeps the best bin of each side, even the weak one.
  cfg.min_map_probability = 0.0;
  HeightModel loose(cfg);
  loose.update(0.05, 0.05, 1.0);
  const auto both = loose.map_estimate(0.05, 0.05);
  REQUIRE(both.below);
  REQUIRE(both.above);
  CHECK(both.below->z_m <= 0.0);
  CHECK(both.above->z_m > 0.0);
  CHECK(both.above->probability > both.below->probability);
}
