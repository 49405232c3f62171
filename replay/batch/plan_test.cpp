// Planning and the manifest: sweep shards, verify inputs (fixtures, folders, lists), golden
// scenarios, the manifest written and read back, and the errors naming what is at fault.
#include <catch2/catch.hpp>

#include <filesystem>

#include "replay/batch/files.hpp"
#include "replay/batch/plan.hpp"
#include "replay/batch/test_support.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using namespace orthosonar::batch;

TEST_CASE("sweep plan: one task per scene, seed and chunk of cells and the reference cell on the first", "[batch]") {
  SweepPlanSpec s;
  s.scenes = {"aircraft", "harbor"};
  s.seeds = {1, 2};
  s.cells = "1/30,3/30,5/90";
  s.cells_per_task = 2;
  auto p = plan_sweep(s, "/tmp/plan-x");
  REQUIRE(p.ok());
  REQUIRE(p->tasks.size() == 8);
  CHECK(p->tasks[0].name == "aircraft/seed1/1m30-3m30");
  CHECK(p->tasks[1].name == "aircraft/seed1/5m90-5m90");
  CHECK(p->tasks[7].name == "harbor/seed2/5m90-5m90");
  CHECK(p->tasks[0].spec.at("reference") == true);
  CHECK(p->tasks[1].spec.at("reference") == false);
  CHECK(p->tasks[1].spec.at("cells").size() == 1);
  s.cells_per_task = 0;
  auto whole = plan_sweep(s, "/tmp/plan-x");
  REQUIRE(whole.ok());
  REQUIRE(whole->tasks.size() == 4);
  CHECK(whole->tasks[3].name == "harbor/seed2");

  SweepPlanSpec bad = s;
  bad.scenes = {"atlantis"};
  CHECK(plan_sweep(bad, "p").error().message.find("sweep plan: --scenes") == 0);
  bad = s;
  bad.cells_per_task = -1;
  CHECK(plan_sweep(bad, "p").error().message == "sweep plan: --cells-per-task must be >= 0");
  bad = s;
  bad.systems = ",";
  CHECK(plan_sweep(bad, "p").error().message == "sweep plan: --systems is empty");
  bad = s;
  bad.model_path = "/no/such/model.pt";
  CHECK(plan_sweep(bad, "p").error().message == "sweep plan: --model '/no/such/model.pt' not found");
}

TEST_CASE("verify plan: fixtures beside their digests, folders, lists and names made unique", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  testing::write_file(d / "a" / "x.mcap", "1");
  testing::write_file(d / "a" / "x.digest.json", "{}");
  testing::write_file(d / "b" / "x.mcap", "2");
  testing::write_file(d / "b" / "x.mcap.digest.json", "{}");
  testing::write_file(d / "list.txt", "# fixtures\nb/x.mcap  a/x.digest.json   # a comment\n\n");
  VerifyPlanSpec s;
  s.inputs = {(d / "a").string(), (d / "b" / "x.mcap").string(), (d / "list.txt").string()};
  auto p = plan_verify(s, (d / "plan").string());
  REQUIRE(p.ok());
  REQUIRE(p->tasks.size() == 3);
  CHECK(p->tasks[0].name == "x");
  CHECK(p->tasks[1].name == "x~2");
  CHECK(p->tasks[2].name == "x~3");
  CHECK(p->tasks[1].spec.at("expect") == (d / "b" / "x.mcap.digest.json").string());
  CHECK(p->tasks[2].spec.at("fixture") == (d / "b" / "x.mcap").string());
  CHECK(p->tasks[2].spec.at("expect") == (d / "a" / "x.digest.json").string());

  testing::write_file(d / "c" / "lonely.mcap", "3");
  s.inputs = {(d / "c" / "lonely.mcap").string()};
  CHECK(plan_verify(s, "p").error().message.find("no expected digest for '" + (d / "c" / "lonely.mcap").string()) !=
        std::string::npos);
  testing::write_file(d / "bad.txt", "a.mcap\n");
  s.inputs = {(d / "bad.txt").string()};
  CHECK(plan_verify(s, "p").error().message ==
        "verify plan: " + (d / "bad.txt").string() + " line 1: expected 'FIXTURE.mcap EXPECTED.json'");
  s.inputs = {};
  CHECK(plan_verify(s, "p").error().message == "verify plan: no fixtures given");
}

TEST_CASE("golden plan: scenarios given and none is an error", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  testing::write_file(d / "harbor.yaml", "x");
  GoldenPlanSpec g;
  CHECK(plan_golden(g, "p").error().message.find("golden plan: no scenarios given") == 0);
  g.scenarios = {(d / "harbor.yaml").string()};
  g.images = false;
  auto p = plan_golden(g, (d / "plan").string());
  REQUIRE(p.ok());
  CHECK(p->tasks.at(0).name == "harbor");
  CHECK(p->common.at("images") == false);
  g.scenarios.push_back((d / "nope.yaml").string());
  CHECK(plan_golden(g, "p").error().message == "golden plan: scenario '" + (d / "nope.yaml").string() + "' not found");
}

TEST_CASE("manifest: written and read back and another plan's results kept unless replaced", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 3);
  auto back = load_plan(p.dir);
  REQUIRE(back.ok());
  CHECK(back->kind == "verify");
  CHECK(back->common == p.common);
  REQUIRE(back->tasks.size() == 3);
  for (size_t i = 0; i < 3; ++i) {
    CHECK(back->tasks[i].name == p.tasks[i].name);
    CHECK(back->tasks[i].spec == p.tasks[i].spec);
  }
  CHECK(*read_text((fs::path(p.dir) / "tasks.txt").string()) == "0 f0\n1 f1\n2 f2\n");

  testing::write_file(fs::path(p.dir) / "results" / "0" / "result.json", "{}");
  Plan other = p;
  other.tasks.pop_back();
  CHECK(write_plan(p, false).ok());  // the same plan: results kept
  CHECK(fs::exists(fs::path(p.dir) / "results" / "0" / "result.json"));
  CHECK(write_plan(other, false).error().message.find("already holds another plan with results") != std::string::npos);
  REQUIRE(write_plan(other, true).ok());
  CHECK_FALSE(fs::exists(fs::path(p.dir) / "results" / "0"));
  CHECK(load_plan(p.dir)->tasks.size() == 2);
}

TEST_CASE("load_plan: errors name the folder or the manifest", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  CHECK(load_plan(d.string()).error().message.find("is not a batch plan (no manifest.json") != std::string::npos);
  const std::string m = (d / "manifest.json").string();
  testing::write_file(m, R"({"orthosonar_batch_plan": 2, "kind": "verify", "common": {}, "tasks": []})");
  CHECK(load_plan(d.string()).error().message == m + ": plan version 2 (this orthosonar reads 1)");
  testing::write_file(m, R"({"orthosonar_batch_plan": 1, "kind": "bake", "common": {}, "tasks": []})");
  CHECK(load_plan(d.string()).error().message == m + ": unknown kind 'bake'");
  testing::write_file(m, R"({"orthosonar_batch_plan": 1, "kind": "golden", "common": {},
    "tasks": [{"index": 1, "name": "a", "spec": {}}]})");
  CHECK(load_plan(d.string()).error().message == m + ": task 0 has index 1");
  testing::write_file(m, "{");
  CHECK(load_plan(d.string()).error().message.find(m + ": not valid JSON") == 0);
}
