// Merging a verify plan's results: summary and JUnit XML (one case per task, a differing
// digest a <failure>, a missing or stale result an <error>), exit codes 0 / 1 / 2, cut
// inputs reported through the callback; XML escaping.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "replay/batch/files.hpp"
#include "replay/batch/merge.hpp"
#include "replay/batch/state.hpp"
#include "replay/batch/test_support.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using namespace orthosonar::batch;
using nlohmann::json;

namespace {

void write_current(const Plan& p, size_t i, json r) {
  json inputs;
  r["key"] = *task_key(p, p.tasks[i], nullptr, &inputs);
  r["inputs"] = inputs;
  testing::write_file(fs::path(result_dir(p, i)) / "result.json", r.dump(2));
}

}  // namespace

TEST_CASE("merge (verify): JUnit XML and summary, exit 0 / 1 / 2", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 3);
  std::ostringstream out, log;
  std::vector<std::string> cut;
  MergeOptions o;
  o.out = &out;
  o.log = &log;
  o.on_cut_input = [&](const std::string& w) { cut.push_back(w); };
  for (size_t i = 0; i < 3; ++i) write_current(p, i, {{"passed", true}, {"got", "abc"}, {"wall_s", 1.5}});
  CHECK(merge(p, o) == 0);
  const fs::path merged = fs::path(p.dir) / "merged";
  auto xml = read_text((merged / "junit.xml").string());
  REQUIRE(xml.ok());
  CHECK(xml->find("tests=\"3\" failures=\"0\" errors=\"0\" time=\"4.500\"") != std::string::npos);
  CHECK(out.str().find("| f1 | identical: abc |") != std::string::npos);
  CHECK(out.str().find("3 of 3 passed, 0 failed, 0 missing.") != std::string::npos);
  CHECK(cut.empty());

  write_current(p, 1, {{"passed", false}, {"message", "expected 1, got 2\n  map: x\n"}, {"input_cut", "f1 cut at 99"}});
  out.str("");
  o.out_dir = (d / "elsewhere").string();
  CHECK(merge(p, o) == 1);
  xml = read_text((d / "elsewhere" / "junit.xml").string());
  CHECK(xml->find("failures=\"1\" errors=\"0\"") != std::string::npos);
  CHECK(xml->find("<failure message=\"expected 1, got 2\" type=\"digest\">") != std::string::npos);
  CHECK(out.str().find("| f1 | DIFFERENT: expected 1, got 2 (INPUT CUT SHORT) |") != std::string::npos);
  REQUIRE(cut.size() == 1);
  CHECK(cut[0] == "batch task 1 (f1): f1 cut at 99");
  CHECK(read_json_file((d / "elsewhere" / "summary.json").string())->at("input_cut_tasks").size() == 1);

  // An input changed after task 2 ran: its result is stale, merged as missing.
  testing::write_file(p.tasks[2].spec.at("fixture").get<std::string>(), "changed");
  log.str("");
  CHECK(merge(p, o) == 2);
  xml = read_text((d / "elsewhere" / "junit.xml").string());
  CHECK(xml->find("failures=\"1\" errors=\"1\"") != std::string::npos);
  CHECK(xml->find("<error message=\"no result: ") != std::string::npos);
  CHECK(log.str().find("1 of 3 task results missing (plan " + p.dir + "):\n  task 2 (f2): stale:") != std::string::npos);
  CHECK(log.str().find("log " + log_path(p, 2)) != std::string::npos);
}

TEST_CASE("merge (sweep): missing shards named, nothing written", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  SweepPlanSpec s;
  s.scenes = {"aircraft"};
  s.seeds = {1};
  s.cells = "1/30,3/30";
  s.cells_per_task = 1;
  auto p = plan_sweep(s, (d / "plan").string());
  REQUIRE(p.ok());
  REQUIRE(write_plan(*p, false).ok());
  std::ostringstream out, log;
  MergeOptions o;
  o.out = &out;
  o.log = &log;
  CHECK(merge(*p, o) == 2);
  CHECK(log.str().find("2 of 2 task results missing") != std::string::npos);
  CHECK(log.str().find("task 1 (aircraft/seed1/3m30-3m30): missing: no result") != std::string::npos);
  CHECK(out.str().empty());
  CHECK_FALSE(fs::exists(fs::path(p->dir) / "merged"));
}

TEST_CASE("xml_escape: markup escaped, control characters replaced", "[batch]") {
  CHECK(xml_escape("a<b>&\"c'") == "a&lt;b&gt;&amp;&quot;c&#39;");
  CHECK(xml_escape(std::string("x\x01y\tz\n", 6)) == "x?y\tz\n");
}
