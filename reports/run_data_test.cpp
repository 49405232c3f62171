#include "reports/run_data.hpp"

#include <catch2/catch.hpp>
#include <fstream>

#include "reports/synthetic_run.hpp"
#include "reports/test_dir.hpp"

using namespace orthosonar;
using namespace orthosonar::reports;

TEST_CASE("TUM trajectories round-trip and malformed lines are reported", "[report]") {
  const auto dir = testing::test_dir("tum");
  Trajectory t(3);
  t[1].t_s = 1.25;
  t[1].position = {1, 2, -3};
  t[2].q_xyzw = {0, 0, 0.70710678, 0.70710678};
  REQUIRE(write_tum((dir / "t.tum").string(), t).ok());
  auto back = read_tum((dir / "t.tum").string());
  REQUIRE(back.ok());
  REQUIRE(back->size() == 3);
  CHECK(back->at(1).t_s == 1.25);
  CHECK(back->at(1).position == Eigen::Vector3d(1, 2, -3));
  std::ofstream(dir / "bad.tum") << "# comment\n0 1 2 3 0 0 0 1\n1 2 3\n";
  auto bad = read_tum((dir / "bad.tum").string());
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("line 3") != std::string::npos);
}

TEST_CASE("a synthetic output directory loads completely", "[report]") {
  const auto dir = testing::test_dir("load_run");
  REQUIRE(write_synthetic_run(dir.string()).ok());
  auto run = load_run(dir.string());
  REQUIRE(run.ok());
  CHECK(run->mesh.has_value());
  REQUIRE(run->truth.has_value());
  CHECK(run->truth->size() == 161);
  REQUIRE(run->systems.size() == 3);
  CHECK(run->systems[0].name == "fusion");
  CHECK(run->systems[1].name == "submap");
  CHECK(run->systems[0].has_map);
  CHECK(run->systems[0].has_metrics);
  CHECK(run->systems[0].runtime.size() == 2);
  CHECK(run->software_version == "synthetic");
  CHECK(run->scene == "synthetic_pilings");
  CHECK(run->digest_overall == std::string(64, 'f'));
  REQUIRE(run->grid.has_value());
  CHECK(run->grid->cells.size() == 45);
  CHECK(run->notes.empty());
}

TEST_CASE("a missing or empty run directory is an error, missing parts are notes", "[report]") {
  const auto dir = testing::test_dir("empty_run");
  CHECK_FALSE(load_run((dir / "nope").string()).ok());
  CHECK_FALSE(load_run(dir.string()).ok());
  std::ofstream(dir / "summary.json") << "{\"software_version\": \"x\"}";
  auto run = load_run(dir.string());
  REQUIRE(run.ok());
  CHECK(run->notes.size() >= 4);
  std::ofstream(dir / "grid.json") << "{\"cells\": 3}";
  auto run2 = load_run(dir.string());
  REQUIRE(run2.ok());
  CHECK_FALSE(run2->grid.has_value());
}
