#pragma once
// The command line of `orthosonar batch` (tools/cmd_batch.cpp): the arguments of its
// subcommands and their registration with CLI11. The batch engine is replay/batch/.
#include <string>

#include "replay/batch/engine.hpp"
#include "replay/batch/plan.hpp"
#include "replay/run/mission.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {

struct BatchPlanArgs {
  std::string out = "plan";
  bool replace = false;
  batch::SweepPlanSpec sweep;  // --cells, --cells-per-task, --systems, --model
  std::string scenes = "marina1,marina2,harbor,aircraft";
  std::string seeds = "1-5";
  run::MissionFlags flags{600.0, false, "full", false, {}, false};  // --duration, --resolution
  std::string sim_config, run_config;
  bool no_report = false;
  batch::VerifyPlanSpec verify;  // inputs, --systems
  batch::GoldenPlanSpec golden;  // scenarios
  bool no_images = false;
};

struct BatchTaskArgs {  // run, merge, status
  std::string plan;
  long task = -1;
  int threads = 0;
  int attempt = 1;
  bool force = false;
  std::string out;
};

struct BatchEngineArgs {  // local, slurm
  std::string plan;
  batch::EngineOptions options;
  int cpus_per_task = 1;
  bool no_merge = false, submit = false, wait = false;
  std::string out;
};

struct BatchArgs {
  BatchPlanArgs plan;
  BatchTaskArgs task;
  BatchEngineArgs local, slurm;
};

// The subcommands, to tell which one was given.
struct BatchApps {
  CLI::App *plan_sweep, *plan_verify, *plan_golden, *run, *merge, *status, *local, *slurm;
  CLI::Option *seeds, *duration, *resolution;  // of plan sweep: given or not
};
// Registers every subcommand of `batch` and its options on `sub`, bound to `args`.
BatchApps add_batch_options(CLI::App& sub, BatchArgs& args);

}  // namespace orthosonar::cli
