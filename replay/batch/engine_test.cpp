// The engines: selection by name; the local engine runs every task as a child process,
// retries a failing one and reports it (a fake task executable stands in for orthosonar);
// the Slurm engine's scripts and its reading of sbatch, sacct and squeue; child processes.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "replay/batch/files.hpp"
#include "replay/batch/local_engine.hpp"
#include "replay/batch/process.hpp"
#include "replay/batch/slurm_engine.hpp"
#include "replay/batch/test_support.hpp"

namespace fs = std::filesystem;
using namespace orthosonar;
using namespace orthosonar::batch;

namespace {

// A stand-in for `orthosonar batch run PLAN --task I --attempt A --threads T`: records its
// arguments, fails every attempt of task `fail_task` up to `fail_attempts`.
std::string fake_executable(const fs::path& dir, int fail_task, int fail_attempts) {
  const fs::path exe = dir / "fake-orthosonar";
  testing::write_file(exe, "#!/bin/sh\necho \"$*\" >>\"$3/calls.txt\"\n"
                           "if [ \"$5\" = " + std::to_string(fail_task) + " ] && [ \"$7\" -le " +
                               std::to_string(fail_attempts) + " ]; then exit 3; fi\nexit 0\n");
  fs::permissions(exe, fs::perms::owner_all);
  return exe.string();
}

}  // namespace

TEST_CASE("make_engine: local and slurm by name and others an error", "[batch]") {
  CHECK((*make_engine("local", {}))->name() == "local");
  CHECK((*make_engine("slurm", {}))->name() == "slurm");
  CHECK(make_engine("kubernetes", {}).error().message == "unknown batch engine 'kubernetes' (engines: local, slurm)");
  CHECK((*make_engine("local", {}))->wait().error().message == "nothing submitted");
  CHECK((*make_engine("slurm", {}))->wait().error().message == "nothing submitted");
}

TEST_CASE("local engine: every task run, a failing one retried, exit 2 when it never passes", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 3);
  std::ostringstream log;
  EngineOptions o;
  o.log = &log;
  o.local.merge = false;
  o.local.jobs = 2;
  o.threads = 4;
  o.retries = 1;
  o.executable = fake_executable(d, 1, 1);  // task 1 fails once
  auto engine = make_engine("local", o);
  REQUIRE(engine.ok());
  REQUIRE((*engine)->submit(p).ok());
  auto code = (*engine)->wait();
  REQUIRE(code.ok());
  CHECK(*code == 0);
  CHECK(log.str().find("task 1 (f1) attempt 1 failed (exit 3), retrying; log " + log_path(p, 1)) != std::string::npos);
  CHECK(log.str().find("3 of 3 tasks done, 0 failed") != std::string::npos);
  const std::string calls = *read_text((fs::path(p.dir) / "calls.txt").string());
  CHECK(calls.find("batch run " + p.dir + " --task 1 --attempt 2 --threads 4") != std::string::npos);
  CHECK(calls.find("--task 0 --attempt 2") == std::string::npos);
  CHECK(read_text(log_path(p, 1))->find("[orthosonar batch local] task 1 attempt 2") != std::string::npos);

  o.executable = fake_executable(d, 2, 99);  // task 2 always fails
  LocalEngine again(o);
  log.str("");
  REQUIRE(again.submit(p).ok());
  CHECK(*again.wait() == 2);
  CHECK(log.str().find("task 2 (f2) FAILED after 2 attempt(s)") != std::string::npos);
  CHECK(log.str().find("2 of 3 tasks done, 1 failed") != std::string::npos);

  o.executable = (d / "no-such-program").string();
  LocalEngine missing(o);
  CHECK(missing.submit(p).error().message.find("cannot start '" + o.executable + "'") == 0);
}

TEST_CASE("slurm engine: the array and merge scripts", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  const Plan p = testing::verify_plan(d, 3);
  EngineOptions o;
  o.threads = 2;
  o.retries = 1;
  o.slurm.max_parallel = 2;
  o.slurm.partition = "short";
  o.slurm.extra = "--mem=4G;;--account=x";
  o.merge.out_dir = "/out/it's";
  o.allow_incomplete = true;
  const SbatchScripts s = sbatch_scripts(p, o, "/opt/orthosonar");
  CHECK(s.array.find("#SBATCH --job-name=orthosonar-verify\n#SBATCH --partition=short\n#SBATCH --mem=4G\n"
                     "#SBATCH --account=x\n#SBATCH --array=0-2%2\n#SBATCH --cpus-per-task=2\n") == 12);
  CHECK(s.array.find("retries=1\n") != std::string::npos);
  CHECK(s.array.find("'/opt/orthosonar' batch run '" + p.dir + "' --attempt") != std::string::npos);
  CHECK(s.merge.find("exec '/opt/orthosonar' batch merge '" + p.dir + "' -o '/out/it'\\''s' --allow-incomplete\n") !=
        std::string::npos);

  SlurmEngine engine(o);
  auto paths = engine.write_scripts(p);
  REQUIRE(paths.ok());
  CHECK(*read_text(paths->first) == sbatch_scripts(p, o, self_executable()).array);
  CHECK((fs::status(paths->second).permissions() & fs::perms::owner_exec) != fs::perms::none);
  Plan empty = p;
  empty.tasks.clear();
  CHECK(engine.write_scripts(empty).error().message == "the plan has no tasks");
}

TEST_CASE("slurm engine: job ids from sbatch, job states from sacct and squeue", "[batch]") {
  CHECK(*job_id_from_sbatch("123\n", 0) == "123");
  CHECK(*job_id_from_sbatch("sbatch: warning: x\n456;cluster\n", 0) == "456");
  CHECK(job_id_from_sbatch("oops\n", 0).error().message == "sbatch printed 'oops', not a job id");
  CHECK(job_id_from_sbatch("denied\n", 1).error().message == "sbatch exited 1: denied");

  const auto sacct = parse_sacct("7_0|COMPLETED|0:0\n7_1|FAILED|2:0\nnoise\n7_2|COMPLETED |0:0\n");
  REQUIRE(sacct.size() == 3);
  CHECK(sacct[2].state == "COMPLETED");
  CHECK(states_summary(sacct) == "COMPLETED 2, FAILED 1 (exit 2:0)");
  const auto squeue = parse_squeue("8|FAILED|512\n9|CANCELLED|9\n");
  REQUIRE(squeue.size() == 2);
  CHECK(squeue[0].exit_code == "2:0");
  CHECK(squeue[1].exit_code == "0:9");
  CHECK(states_summary({}).find("state unknown") == 0);
}

TEST_CASE("child processes: captured output and exit codes, logs appended, shell quoting", "[batch]") {
  const fs::path d = replay::testing::case_dir("batch", Catch::getResultCapture().getCurrentTestName(), true);
  auto c = run_captured({"sh", "-c", "echo out; echo err >&2; exit 3"});
  REQUIRE(c.ok());
  CHECK(c->exit_code == 3);
  CHECK(c->out == "out\nerr\n");
  CHECK(run_captured({"sh", "-c", "kill -9 $$"})->exit_code == 128 + 9);
  CHECK(run_captured({"/no/such/program"}).error().message.find("cannot start '/no/such/program'") == 0);
  const std::string log = (d / "logs" / "x.log").string();
  for (const char* word : {"one", "two"}) {
    auto pid = spawn_logged({"echo", word}, log);
    REQUIRE(pid.ok());
    CHECK(wait_exit_code(*pid) == 0);
  }
  CHECK(*read_text(log) == "one\ntwo\n");
  const std::string tricky = "it's a \"test\" $HOME `x`";
  CHECK(run_captured({"sh", "-c", "printf %s " + shell_quote(tricky)})->out == tricky);
}
