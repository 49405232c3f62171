#pragma once
// Batch runs (docs/BATCH.md): a plan is a folder holding a manifest of independent tasks;
// any engine runs them (`batch local`, a Slurm job array, a Kubernetes Indexed Job), each
// task writing only its own result folder, and `batch merge` gathers the results into the
// outputs the one-machine command writes.
//
//   plan/manifest.json        kind, common settings, the tasks (index, name, spec)
//   plan/tasks.txt            "index name" per line, for people and shell loops
//   plan/results/<i>/         task i's result.json (+ outputs), or failed.json
//   plan/logs/task-<i>.log    engine logs (every attempt appended)
//   plan/fixtures/            sweep: the simulated fixtures (shared by a scene/seed's tasks)
//   plan/slurm/               sbatch scripts and the submitted job ids
//   plan/merged/              batch merge's default output
//
// A task's result carries its key: SHA-256 over the task's spec, the plan's common
// settings, the digests of its input files and of the orthosonar executable. A task whose
// result holds the current key is skipped, so a re-submitted array resumes; a result with
// another key (inputs or code changed) counts as missing at merge.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::cli::batch {

struct Task {
  size_t index = 0;
  std::string name;      // "harbor/seed2/1m30-5m30", a fixture's stem, a scenario's name
  nlohmann::json spec;   // kind-specific
};

struct Plan {
  std::string dir;             // absolute
  std::string kind;            // sweep | verify | golden
  nlohmann::json common;       // settings shared by every task
  std::vector<Task> tasks;
};

// ---- planning ----
struct SweepPlanSpec {
  std::vector<std::string> scenes;
  std::vector<uint64_t> seeds;
  std::string cells = "all";
  int cells_per_task = 0;  // 0: all of a (scene, seed)'s cells in one task
  double duration_s = 600.0;
  std::string resolution = "full";
  std::string sim_config_yaml;
  std::string run_config_yaml;
  std::string systems = "fusion,submap";
  std::string model_path;  // classifier for the inference systems (its bytes are in the key)
  bool report = true;
};
Result<Plan> plan_sweep(const SweepPlanSpec& spec, const std::string& dir);

// `inputs`: fixtures (.mcap, expected digest beside it as <stem>.digest.json or
// <file>.digest.json), directories (every .mcap in them with such a digest), or list files
// (.txt: "fixture.mcap expected.json" per line, paths relative to the list; # comments).
struct VerifyPlanSpec {
  std::vector<std::string> inputs;
  std::string run_config_yaml;
  std::string systems;  // empty: the ones each expected digest names
};
Result<Plan> plan_verify(const VerifyPlanSpec& spec, const std::string& dir);

struct GoldenPlanSpec {
  std::vector<std::string> scenarios;  // empty: golden/scenarios/*.yaml
  bool images = true;
};
Result<Plan> plan_golden(const GoldenPlanSpec& spec, const std::string& dir);

// Writes manifest.json and tasks.txt (creates the folder; refuses a folder holding a
// different plan's results unless `replace`).
Status write_plan(const Plan& plan, bool replace);
Result<Plan> load_plan(const std::string& dir);

// ---- running ----
// The task to run: `given` when set, else $SLURM_ARRAY_TASK_ID, else $JOB_COMPLETION_INDEX
// (Kubernetes Indexed Jobs). Errors say which variable held what.
Result<size_t> task_index(const Plan& plan, std::optional<long> given);

std::string result_dir(const Plan& plan, size_t index);
std::string log_path(const Plan& plan, size_t index);

// SHA-256 of the running executable (/proc/self/exe), computed once.
const std::string& executable_digest();
// The task's key. `known` (a result's "inputs": label -> {path, size, mtime_ns, sha256})
// lets an input file whose path, size and modification time are unchanged reuse its
// recorded digest instead of being read again (a regression suite's fixtures are large);
// `inputs` receives the same record for this key.
Result<std::string> task_key(const Plan& plan, const Task& task, const nlohmann::json* known = nullptr,
                             nlohmann::json* inputs = nullptr);

struct RunTaskOptions {
  int threads = 1;
  int attempt = 1;
  bool force = false;  // run even when the result is current
};
// Runs one task; exit code: 0 done (or skipped as current; a digest difference is a
// result, not a failure), 2 failed (failed.json written, message on stderr).
int run_task(const Plan& plan, size_t index, const RunTaskOptions& options);

// ---- state and merging ----
enum class TaskState { kDone, kFailed, kMissing, kStale };
struct TaskStatus {
  TaskState state = TaskState::kMissing;
  std::string detail;  // failed: the error (and attempt); stale: why
};
// Reads results/<i>/; `check_keys` recomputes each key (hashes the inputs).
TaskStatus task_status(const Plan& plan, const Task& task, bool check_keys);
std::string state_name(TaskState s);

// Gathers the results into `out_dir` (default <plan>/merged). Exit code: 0 everything
// present and passing, 1 verify/golden with a difference, 2 results missing or failed
// (named on stderr with their log paths; JUnit still written for verify/golden).
int merge(const Plan& plan, const std::string& out_dir);

// A file's whole content. Errors name the file.
Result<std::string> read_text(const std::string& path);

// JUnit XML text escaping (attributes and text).
std::string xml_escape(const std::string& s);

}  // namespace orthosonar::cli::batch
