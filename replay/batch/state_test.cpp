// Task state and resume: a result holding the current key is done (and run_task skips it),
// another key is stale, failed.json is a failure with its attempt; the task index from the
// command line or the scheduler's variables.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>

#include "replay/batch/files.hpp"
#include "replay/batch/run.hpp"
#include "replay/batch/state.hpp"
#include "replay/batch/test_support.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using namespace orthosonar::batch;
using nlohmann::json;

namespace {

void write_result(const Plan& p, size_t i, const json& r) {
  testing::write_file(fs::path(result_dir(p, i)) / "result.json", r.dump(2));
}

}  // namespace

TEST_CASE("task state: missing, done with the current key, stale when an input changed, failed", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 2);
  CHECK(task_status(p, p.tasks[0], true).state == TaskState::kMissing);
  CHECK(task_status(p, p.tasks[0], true).detail == "no result");

  json inputs;
  auto key = task_key(p, p.tasks[0], nullptr, &inputs);
  REQUIRE(key.ok());
  CHECK(key->size() == 64);
  CHECK(inputs.at("fixture").at("path") == p.tasks[0].spec.at("fixture"));
  write_result(p, 0, {{"key", *key}, {"inputs", inputs}});
  CHECK(task_status(p, p.tasks[0], true).state == TaskState::kDone);
  CHECK(*task_key(p, p.tasks[1]) != *key);  // another task, another key

  // A recorded digest is reused only while path, size and mtime are unchanged.
  json forged = inputs;
  forged["fixture"]["sha256"] = std::string(64, '0');
  CHECK(*task_key(p, p.tasks[0], &forged) != *key);
  testing::write_file(p.tasks[0].spec.at("fixture").get<std::string>(), "other bytes!");
  CHECK(*task_key(p, p.tasks[0], &forged) == *task_key(p, p.tasks[0]));  // re-hashed
  const TaskStatus stale = task_status(p, p.tasks[0], true);
  CHECK(stale.state == TaskState::kStale);
  CHECK(stale.detail == "the result was made from other inputs or another orthosonar build");
  CHECK(task_status(p, p.tasks[0], false).state == TaskState::kDone);  // keys not checked

  CHECK_FALSE(failure_time(p, 1));
  testing::write_file(fs::path(result_dir(p, 1)) / "failed.json",
                      json{{"error", "boom"}, {"attempt", 2}, {"host", "node7"}}.dump());
  const TaskStatus failed = task_status(p, p.tasks[1], true);
  CHECK(failed.state == TaskState::kFailed);
  CHECK(failed.detail == "boom (attempt 2 on node7)");
  CHECK(failure_time(p, 1));
  CHECK(state_name(TaskState::kStale) == "stale");
}

TEST_CASE("run_task: a current result is skipped and a failing task writes failed.json and no partial folder", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 1);
  json inputs;
  const std::string key = *task_key(p, p.tasks[0], nullptr, &inputs);
  write_result(p, 0, {{"key", key}, {"inputs", inputs}, {"marker", 7}});
  RunTaskOptions o;
  CHECK(run_task(p, 0, o) == 0);
  CHECK(read_json_file(result_dir(p, 0) + "/result.json")->value("marker", 0) == 7);  // untouched

  o.force = true;  // runs: the fixture is not an MCAP file, the task fails
  o.attempt = 3;
  CHECK(run_task(p, 0, o) == 2);
  CHECK_FALSE(fs::exists(result_dir(p, 0) + "/result.json"));
  auto f = read_json_file(result_dir(p, 0) + "/failed.json");
  REQUIRE(f.ok());
  CHECK(f->at("attempt") == 3);
  CHECK(f->at("key") == key);
  CHECK_FALSE(f->at("error").get<std::string>().empty());
  for (const auto& e : fs::directory_iterator(fs::path(p.dir) / "results"))
    CHECK(e.path().filename().string().find(".partial.") == std::string::npos);
  CHECK(task_status(p, p.tasks[0], true).state == TaskState::kFailed);
}

TEST_CASE("task index: --task, then $SLURM_ARRAY_TASK_ID, then $JOB_COMPLETION_INDEX", "[batch]") {
  Plan p;
  p.tasks.resize(4);
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("JOB_COMPLETION_INDEX");
  CHECK(task_index(p, std::nullopt).error().message.find("no task index") == 0);
  CHECK(*task_index(p, 2) == 2);
  CHECK(task_index(p, 4).error().message == "--task = 4: the plan has tasks 0..4-1");
  ::setenv("JOB_COMPLETION_INDEX", "3", 1);
  CHECK(*task_index(p, std::nullopt) == 3);
  ::setenv("SLURM_ARRAY_TASK_ID", "1", 1);
  CHECK(*task_index(p, std::nullopt) == 1);
  CHECK(*task_index(p, 0) == 0);
  ::setenv("SLURM_ARRAY_TASK_ID", "1x", 1);
  CHECK(task_index(p, std::nullopt).error().message == "$SLURM_ARRAY_TASK_ID is '1x', not a task index");
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  ::unsetenv("JOB_COMPLETION_INDEX");

  ::setenv("SLURM_CPUS_PER_TASK", "3", 1);
  CHECK(default_task_threads() == 3);
  ::setenv("SLURM_CPUS_PER_TASK", "0", 1);
  CHECK(default_task_threads() == 1);
  ::unsetenv("SLURM_CPUS_PER_TASK");
}
