// The sweep's cell and seed lists, the exact round trip of a cell's result through JSON
// (what lets `batch merge` rebuild the one-machine bytes from shards), and the seed tables
// pooled over seeds.
#include <catch2/catch.hpp>
#include <rapidcheck/catch.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "replay/run/sweep.hpp"

namespace orthosonar::run {
namespace {

CellResult make_cell(double d, double r, double mae, double rmse, int64_t n, double dr, double slam) {
  CellResult c;
  c.cell = {d, r};
  c.keyframes = 7;
  c.ate_dr_m = dr;
  c.ate_slam_m = slam;
  c.digest = "abc";
  CellSystem s;
  s.system = "fusion";
  s.coverage_voxels = 100;
  s.accuracy_count = n;
  s.mae_m = mae;
  s.rmse_m = rmse;
  c.systems.push_back(s);
  return c;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("parse_cells: all, lists in grid order, errors naming the item", "[sweep]") {
  CHECK(parse_cells("all")->size() == 15);
  auto c = parse_cells("5/90, 1/30,3/30,1/30");
  REQUIRE(c.ok());
  REQUIRE(c->size() == 3);
  CHECK(cell_name((*c)[0]) == "1m30");
  CHECK(cell_name((*c)[1]) == "3m30");
  CHECK(cell_name((*c)[2]) == "5m90");
  for (const char* bad : {"6/30", "3/45", "3", "x/30", "", ",", "3/30,x"}) {
    auto r = parse_cells(bad);
    CHECK_FALSE(r.ok());
  }
  CHECK(parse_cells("3/45").error().message.find("'3/45'") != std::string::npos);
}

TEST_CASE("parse_seeds: ranges and lists, sorted, errors", "[sweep]") {
  CHECK(*parse_seeds("1-5") == std::vector<uint64_t>{1, 2, 3, 4, 5});
  CHECK(*parse_seeds("7,2,3-4,2") == std::vector<uint64_t>{2, 3, 4, 7});
  for (const char* bad : {"", "5-1", "a", "1-", "-3", "1.5", "0-20000"}) CHECK_FALSE(parse_seeds(bad).ok());
}

TEST_CASE("a cell's result survives JSON exactly (doubles bit for bit)", "[sweep][property][rapidcheck]") {
  rc::prop("round trip", [] {
    CellResult c;
    c.cell = {static_cast<double>(*rc::gen::inRange(1, 6)), 30.0 * *rc::gen::inRange(1, 4)};
    c.keyframes = *rc::gen::inRange<int64_t>(0, 100000);
    // Any finite double, including subnormals and values with 17 significant digits.
    auto any_double = rc::gen::map(rc::gen::arbitrary<uint64_t>(), [](uint64_t bits) {
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return std::isfinite(d) ? d : 0.1;
    });
    if (*rc::gen::arbitrary<bool>()) c.ate_dr_m = *any_double;
    if (*rc::gen::arbitrary<bool>()) c.ate_slam_m = *any_double;
    if (*rc::gen::arbitrary<bool>()) c.heading_rms_dr_deg = *any_double;
    if (*rc::gen::arbitrary<bool>()) c.heading_rms_slam_deg = *any_double;
    c.digest = *rc::gen::container<std::string>(rc::gen::elementOf(std::string("0123456789abcdef")));
    c.slam_runtime.count = 3;
    c.slam_runtime.sum_ms = *any_double;
    const int n = *rc::gen::inRange(0, 4);
    for (int k = 0; k < n; ++k) {
      CellSystem s;
      s.system = "s" + std::to_string(k);
      s.coverage_voxels = *rc::gen::arbitrary<int64_t>();
      s.accuracy_count = *rc::gen::inRange<int64_t>(0, 1 << 30);
      s.mae_m = *any_double;
      s.rmse_m = *any_double;
      s.true_pose_count = *rc::gen::inRange<int64_t>(0, 1 << 30);
      s.true_pose_mae_m = *any_double;
      s.true_pose_rmse_m = *any_double;
      c.systems.push_back(s);
    }
    const std::string text = cell_result_to_json(c).dump();
    auto back = cell_result_from_json(nlohmann::json::parse(text));
    RC_ASSERT(back.ok());
    RC_ASSERT(back->cell.distance_m == c.cell.distance_m);
    RC_ASSERT(back->keyframes == c.keyframes);
    RC_ASSERT(back->ate_dr_m.has_value() == c.ate_dr_m.has_value());
    if (c.ate_dr_m) RC_ASSERT(same_bits(*back->ate_dr_m, *c.ate_dr_m));
    if (c.ate_slam_m) RC_ASSERT(same_bits(*back->ate_slam_m, *c.ate_slam_m));
    RC_ASSERT(back->heading_rms_dr_deg.has_value() == c.heading_rms_dr_deg.has_value());
    RC_ASSERT(back->heading_rms_slam_deg.has_value() == c.heading_rms_slam_deg.has_value());
    if (c.heading_rms_dr_deg) RC_ASSERT(same_bits(*back->heading_rms_dr_deg, *c.heading_rms_dr_deg));
    if (c.heading_rms_slam_deg) RC_ASSERT(same_bits(*back->heading_rms_slam_deg, *c.heading_rms_slam_deg));
    RC_ASSERT(back->digest == c.digest);
    RC_ASSERT(same_bits(back->slam_runtime.sum_ms, c.slam_runtime.sum_ms));
    RC_ASSERT(back->systems.size() == c.systems.size());
    for (size_t k = 0; k < c.systems.size(); ++k) {
      RC_ASSERT(back->systems[k].system == c.systems[k].system);
      RC_ASSERT(back->systems[k].coverage_voxels == c.systems[k].coverage_voxels);
      RC_ASSERT(back->systems[k].accuracy_count == c.systems[k].accuracy_count);
      RC_ASSERT(same_bits(back->systems[k].mae_m, c.systems[k].mae_m));
      RC_ASSERT(same_bits(back->systems[k].rmse_m, c.systems[k].rmse_m));
      RC_ASSERT(back->systems[k].true_pose_count == c.systems[k].true_pose_count);
      RC_ASSERT(same_bits(back->systems[k].true_pose_mae_m, c.systems[k].true_pose_mae_m));
      RC_ASSERT(same_bits(back->systems[k].true_pose_rmse_m, c.systems[k].true_pose_rmse_m));
    }
  });
}

TEST_CASE("cell_result_from_json names what is wrong", "[sweep]") {
  auto r = cell_result_from_json(nlohmann::json{{"distance_m", 1.0}});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("cell result") != std::string::npos);
}

TEST_CASE("seed tables pool MAE by point count and RMSE in quadrature, outputs written per scene/seed", "[sweep]") {
  SweepReport a, b;
  a.scene = b.scene = "harbor";
  // seed 1: 100 points at MAE 0.1 / RMSE 0.2; seed 2: 300 points at MAE 0.3 / RMSE 0.4.
  a.cells = {make_cell(1, 30, 0.1, 0.2, 100, 2.0, 1.0)};
  b.cells = {make_cell(1, 30, 0.3, 0.4, 300, 1.0, 2.0)};
  const std::string md = seeds_markdown({a, b}, {1, 2});
  CHECK(md.find("| 1 | 0.100 | 0.200 | n/a / n/a | 0.50 | 1/1 |") != std::string::npos);
  CHECK(md.find("| 2 | 0.300 | 0.400 | n/a / n/a | 2.00 | 0/1 |") != std::string::npos);
  // pooled MAE (0.1*100 + 0.3*300)/400 = 0.25; RMSE sqrt((0.04*100 + 0.16*300)/400) = 0.3606;
  // median of the ratios 0.5 and 2 = 1.25; SLAM <= DR in 1 of 2 cells.
  CHECK(md.find("| pooled | 0.250 | 0.361 | n/a / n/a | 1.25 | 1/2 |") != std::string::npos);

  const auto dir = std::filesystem::temp_directory_path() / "orthosonar_sweep_set_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  REQUIRE(write_sweep_set({a, b}, {1, 2}, dir.string()).ok());
  for (const char* f : {"seeds.md", "seeds.json", "harbor/seed1/grid.json", "harbor/seed2/tables.md",
                        "harbor/seed2/runtime.md"})
    CHECK(std::filesystem::exists(dir / f));
  CHECK(slurp(dir / "seeds.md") == md);
  // Tables carry no timing: the same bytes whatever the runtimes were.
  const std::string tables = slurp(dir / "harbor/seed1/tables.md");
  a.cells[0].systems[0].runtime.add(123.0);
  a.fuse_wall_s = 99.0;
  REQUIRE(write_sweep_outputs(a, (dir / "again").string()).ok() == false);  // folder missing: an error
  std::filesystem::create_directories(dir / "again");
  REQUIRE(write_sweep_outputs(a, (dir / "again").string()).ok());
  CHECK(slurp(dir / "again/tables.md") == tables);
  CHECK(slurp(dir / "again/grid.json") == slurp(dir / "harbor/seed1/grid.json"));
  CHECK(slurp(dir / "again/runtime.md") != slurp(dir / "harbor/seed1/runtime.md"));
  // A subset of the grid: cells not run print as "–".
  CHECK(tables.find("| 30° | 100 | – | – | – | – |") != std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace orthosonar::run
