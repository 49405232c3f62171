#pragma once
// The engines that run a plan's tasks, behind one interface: each task is the command
// `orthosonar batch run PLAN --task I --attempt A --threads T` (run.hpp), a failed task is
// retried, and the results are merged (merge.hpp). local_engine.hpp runs them on this
// machine, slurm_engine.hpp as a Slurm job array with a dependent merge job.
#include <iostream>
#include <memory>
#include <string>

#include "core/result.hpp"
#include "replay/batch/merge.hpp"
#include "replay/batch/plan.hpp"

namespace orthosonar::batch {

struct EngineOptions {
  std::string executable;  // the orthosonar executable the tasks run; empty: this process's own
  int threads = 1;         // per task (Slurm: CPUs per task)
  int retries = 2;         // retries of a failed task
  MergeOptions merge;      // the merge's output folder and streams (Slurm: out_dir only)
  bool allow_incomplete = false;  // the merge accepts cut inputs (--allow-incomplete)
  std::ostream* log = &std::cerr;  // progress: tasks done, failed, retried

  struct Local {
    int jobs = 2;       // tasks at once
    bool merge = true;  // merge afterwards
  } local;

  struct Slurm {
    std::string partition;
    int max_parallel = 0;     // %K throttle of the array (0: no limit)
    std::string time_limit;   // sbatch --time
    std::string extra;        // extra #SBATCH lines, ';'-separated
    double timeout_s = 0.0;   // wait(): give up after this long (0: never)
    double poll_s = 2.0;      // wait(): seconds between polls
  } slurm;
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string name() const = 0;  // "local", "slurm"
  // Hands every task of `plan` (and the merge) to the engine. Errors when nothing could be
  // started or submitted; the message names the program or file at fault.
  virtual Status submit(const Plan& plan) = 0;
  // Until the submitted tasks and the merge are through. The exit code of the batch: the
  // merge's (0 all present and passing, 1 a difference, 2 results missing); without a merge
  // 0 when every task is done, else 2. An error when the engine lost track of its work.
  virtual Result<int> wait() = 0;
};

// "local" or "slurm"; other names are an error listing these.
Result<std::unique_ptr<Engine>> make_engine(const std::string& name, const EngineOptions& options);

// options.executable, or this process's own executable when it is empty.
std::string task_executable(const EngineOptions& options);

}  // namespace orthosonar::batch
