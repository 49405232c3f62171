#pragma once
// Running one task of a plan (plan.hpp) into its result folder: a sweep task simulates or
// reuses its fixture and replays its keyframe cells, a verify task replays a fixture and
// compares the digest, a golden task runs `orthosonar golden --check` in a child process.
// The engines (engine.hpp) run each task as `orthosonar batch run PLAN --task I`.
#include <optional>
#include <string>

#include "core/result.hpp"
#include "replay/batch/plan.hpp"

namespace orthosonar::batch {

// The task to run: `given` when set, else $SLURM_ARRAY_TASK_ID, else $JOB_COMPLETION_INDEX
// (Kubernetes Indexed Jobs). Errors say which variable held what.
Result<size_t> task_index(const Plan& plan, std::optional<long> given);

// A task's threads when none are given: $SLURM_CPUS_PER_TASK when set and > 0, else 1.
int default_task_threads();

struct RunTaskOptions {
  int threads = 1;
  int attempt = 1;
  bool force = false;       // run even when the result is current
  std::string executable;   // golden tasks: the orthosonar executable; empty: this process's own
};
// Runs one task (progress on stderr); exit code: 0 done (or skipped as current; a digest
// difference is a result, not a failure), 2 failed (failed.json written, message on stderr).
int run_task(const Plan& plan, size_t index, const RunTaskOptions& options);

}  // namespace orthosonar::batch
