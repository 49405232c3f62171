#pragma once
// The state of a plan's tasks, read from its folder (plan.hpp): where a task's result and
// log live, the task's key, and whether its result is done, failed, stale or missing.
//
// A task's result carries its key: SHA-256 over the task's spec, the plan's common
// settings, the digests of its input files and of the orthosonar executable. A task whose
// result holds the current key is skipped, so a re-submitted plan resumes; a result with
// another key (inputs or code changed) is stale and counts as missing at merge.
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/result.hpp"
#include "replay/batch/plan.hpp"

namespace orthosonar::batch {

std::string result_dir(const Plan& plan, size_t index);  // <plan>/results/<i>
std::string log_path(const Plan& plan, size_t index);    // <plan>/logs/task-<i>.log

// SHA-256 of the running executable (/proc/self/exe), computed once.
const std::string& executable_digest();
// The task's key. `known` (a result's "inputs": label -> {path, size, mtime_ns, sha256})
// lets an input file whose path, size and modification time are unchanged reuse its
// recorded digest instead of being read again (a regression suite's fixtures are large);
// `inputs` receives the same record for this key.
Result<std::string> task_key(const Plan& plan, const Task& task, const nlohmann::json* known = nullptr,
                             nlohmann::json* inputs = nullptr);

enum class TaskState { kDone, kFailed, kMissing, kStale };
struct TaskStatus {
  TaskState state = TaskState::kMissing;
  std::string detail;  // failed: the error (and attempt); stale: why
};
// Reads results/<i>/; `check_keys` recomputes each key (hashes the inputs).
TaskStatus task_status(const Plan& plan, const Task& task, bool check_keys);
std::string state_name(TaskState s);

// When task `index`'s failed.json was written (none: no failure recorded), to tell one
// submission's failures from those an earlier one left.
std::optional<std::filesystem::file_time_type> failure_time(const Plan& plan, size_t index);

}  // namespace orthosonar::batch
