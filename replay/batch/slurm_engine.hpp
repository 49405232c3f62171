#pragma once
// The Slurm engine (engine.hpp): a plan as a Slurm job array (one array index per task,
// a failed task retried in place) and a merge job that runs after the whole array
// (afterany), submitted with sbatch and followed with squeue and sacct. The scripts are
// written to <plan>/slurm/ and can be submitted by hand as well.
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "replay/batch/engine.hpp"
#include "replay/batch/state.hpp"

namespace orthosonar::batch {

// The text of the two sbatch scripts for `plan`, running `executable`.
struct SbatchScripts {
  std::string array;
  std::string merge;
};
SbatchScripts sbatch_scripts(const Plan& plan, const EngineOptions& options, const std::string& executable);

// The job id `sbatch --parsable` printed ("123" or "123;cluster", warnings before it), or an
// error quoting what it printed and its exit code.
Result<std::string> job_id_from_sbatch(const std::string& printed, int exit_code);

// A job's (or an array task's) state as Slurm reports it.
struct JobState {
  std::string id;
  std::string state;      // COMPLETED, FAILED, ...
  std::string exit_code;  // "code:signal"
};
// `sacct -X -n -P -o JobID,State,ExitCode` output.
std::vector<JobState> parse_sacct(const std::string& out);
// `squeue -h -r -t all -O JobArrayID:|,State:|,exit_code` output (its exit_code is the raw
// wait status: code = value >> 8).
std::vector<JobState> parse_squeue(const std::string& out);
// "COMPLETED 7, FAILED 1 (exit 2:0)" for a job or an array.
std::string states_summary(const std::vector<JobState>& states);

class SlurmEngine final : public Engine {
 public:
  explicit SlurmEngine(EngineOptions options);
  std::string name() const override { return "slurm"; }
  // Writes <plan>/slurm/array.sbatch and merge.sbatch; returns their paths. Errors: a plan
  // without tasks, a folder that cannot be written.
  Result<std::pair<std::string, std::string>> write_scripts(const Plan& plan);
  // Writes the scripts (unless write_scripts did), submits the array and the merge job and
  // records their ids in <plan>/slurm/jobs.json.
  Status submit(const Plan& plan) override;
  // Follows the jobs until none is queued (progress and failed tasks on `log`), then prints
  // the merge job's log on merge.out; the merge job's exit code. An error at the timeout.
  Result<int> wait() override;

  const std::string& array_job() const { return array_job_; }
  const std::string& merge_job() const { return merge_job_; }

 private:
  EngineOptions options_;
  std::string executable_;
  std::optional<Plan> plan_;
  std::optional<std::pair<std::string, std::string>> scripts_;
  std::map<size_t, std::filesystem::file_time_type> earlier_failures_;  // failed.json before submitting
  std::string array_job_, merge_job_;
};

}  // namespace orthosonar::batch
