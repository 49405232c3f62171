// `orthosonar batch`: work sharded into independent tasks that any engine can run
// (docs/BATCH.md): plan, run one task, merge, status, and the local and Slurm engines.
// Printing only: the batch engine is the library in replay/batch/ (the plan folder is
// described in replay/batch/plan.hpp); the options are in tools/support_batch_args.cpp.
#include <iostream>
#include <map>
#include <sstream>

#include "replay/batch/files.hpp"
#include "replay/batch/merge.hpp"
#include "replay/batch/run.hpp"
#include "replay/batch/slurm_engine.hpp"
#include "replay/batch/state.hpp"
#include "replay/run/sweep.hpp"
#include "replay/verify/golden_scenario.hpp"
#include "tools/support_batch_args.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {

using namespace ::orthosonar::batch;  // NOLINT: this file is the batch library's front end

int batch_fail(const std::string& what, const std::string& m) {
  std::cerr << "orthosonar batch " << what << ": " << m << "\n";
  return 2;
}

// An option's file, or nothing when the option was not given.
Result<std::string> read_file_text(const std::string& path) {
  if (path.empty()) return std::string();
  return read_text(path);
}

// ---------------------------------------------------------------- plan

int finish_plan(Result<Plan> plan, bool replace) {
  if (!plan.ok()) return batch_fail("plan", plan.error().message);
  if (Status s = write_plan(*plan, replace); !s.ok()) return batch_fail("plan", s.error().message);
  std::cout << "plan: " << plan->kind << ", " << plan->tasks.size() << " tasks in " << plan->dir << "\n";
  for (const auto& t : plan->tasks) std::cout << "  " << t.index << " " << t.name << "\n";
  std::cout << "run: orthosonar batch local " << plan->dir << " -j N, or orthosonar batch slurm " << plan->dir
            << " --submit --wait\n";
  return 0;
}

int plan_sweep_cmd(BatchPlanArgs& a) {
  SweepPlanSpec& s = a.sweep;
  std::stringstream ss(a.scenes);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) s.scenes.push_back(item);
  auto seeds = run::parse_seeds(a.seeds);
  if (!seeds.ok()) return batch_fail("plan", "--" + seeds.error().message);
  auto sim = read_file_text(a.sim_config);
  if (!sim.ok()) return batch_fail("plan", "--sim-config: " + sim.error().message);
  // A flag given wins over --sim-config, the file over the flag's default (as sweep, simulate).
  a.flags.seeds = *seeds;
  if (Status st = run::resolve_mission_flags(*sim, a.flags); !st.ok())
    return batch_fail("plan", "--sim-config " + a.sim_config + ": " + st.error().message);
  auto cfg = read_file_text(a.run_config);
  if (!cfg.ok()) return batch_fail("plan", "--config: " + cfg.error().message);
  s.seeds = a.flags.seeds;
  s.duration_s = a.flags.duration_s;
  s.resolution = a.flags.resolution;
  s.sim_config_yaml = *sim;
  s.run_config_yaml = *cfg;
  s.report = !a.no_report;
  return finish_plan(plan_sweep(s, a.out), a.replace);
}

int plan_verify_cmd(BatchPlanArgs& a) {
  auto cfg = read_file_text(a.run_config);
  if (!cfg.ok()) return batch_fail("plan", "--config: " + cfg.error().message);
  a.verify.run_config_yaml = *cfg;
  return finish_plan(plan_verify(a.verify, a.out), a.replace);
}

int plan_golden_cmd(BatchPlanArgs& a) {
  if (a.golden.scenarios.empty()) a.golden.scenarios = verify::default_golden_scenarios();
  a.golden.images = !a.no_images;
  return finish_plan(plan_golden(a.golden, a.out), a.replace);
}

// ---------------------------------------------------------------- run, merge, status

int run_cmd(const BatchTaskArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("run", plan.error().message);
  auto index = task_index(*plan, a.task >= 0 ? std::optional<long>(a.task) : std::nullopt);
  if (!index.ok()) return batch_fail("run", index.error().message);
  RunTaskOptions o;
  o.threads = a.threads > 0 ? a.threads : default_task_threads();
  o.attempt = a.attempt;
  o.force = a.force;
  return run_task(*plan, *index, o);
}

MergeOptions merge_options(const std::string& out) {
  MergeOptions o;
  o.out_dir = out;
  o.on_cut_input = note_cut_input_warning;  // exit 1 for cut inputs unless --allow-incomplete
  return o;
}

int merge_cmd(const BatchTaskArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("merge", plan.error().message);
  return merge(*plan, merge_options(a.out));
}

int status_cmd(const BatchTaskArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("status", plan.error().message);
  std::map<TaskState, int> n;
  for (const auto& t : plan->tasks) {
    const TaskStatus st = task_status(*plan, t, true);
    ++n[st.state];
    std::cout << t.index << " " << t.name << " " << state_name(st.state)
              << (st.detail.empty() ? "" : ": " + st.detail) << "\n";
  }
  std::cout << plan->tasks.size() << " tasks: " << n[TaskState::kDone] << " done, " << n[TaskState::kFailed]
            << " failed, " << n[TaskState::kStale] << " stale, " << n[TaskState::kMissing] << " missing\n";
  return n[TaskState::kDone] == static_cast<int>(plan->tasks.size()) ? 0 : 1;
}

// ---------------------------------------------------------------- engines

EngineOptions engine_options(const BatchEngineArgs& a) {
  EngineOptions o = a.options;
  o.merge = merge_options(a.out);
  o.local.merge = !a.no_merge;
  o.allow_incomplete = allow_incomplete();
  return o;
}

int wait_for(Engine& engine) {
  auto code = engine.wait();
  return code.ok() ? *code : batch_fail(engine.name(), code.error().message);
}

int local_cmd(const BatchEngineArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("local", plan.error().message);
  auto engine = make_engine("local", engine_options(a));
  if (!engine.ok()) return batch_fail("local", engine.error().message);
  if (Status s = (*engine)->submit(*plan); !s.ok()) return batch_fail("local", s.error().message);
  return wait_for(**engine);
}

int slurm_cmd(BatchEngineArgs a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("slurm", plan.error().message);
  a.options.threads = a.cpus_per_task;
  SlurmEngine engine(engine_options(a));
  auto scripts = engine.write_scripts(*plan);
  if (!scripts.ok()) return batch_fail("slurm", scripts.error().message);
  std::cout << "slurm: job array " << scripts->first << " (" << plan->tasks.size() << " tasks), merge "
            << scripts->second << "\n";
  if (!a.submit) {
    std::cout << "submit: id=$(sbatch --parsable " << scripts->first << ") && sbatch --dependency=afterany:$id "
              << scripts->second << "   (or rerun with --submit [--wait])\n";
    return 0;
  }
  if (Status s = engine.submit(*plan); !s.ok()) return batch_fail("slurm", s.error().message);
  std::cout << "slurm: submitted array job " << engine.array_job() << " and merge job " << engine.merge_job() << "\n";
  return a.wait ? wait_for(engine) : 0;
}

// ---------------------------------------------------------------- registration

const bool registered_batch = register_command(
    {"batch", "Shard work into independent tasks: plan, run, merge; run them locally or as a Slurm job array",
     [](CLI::App& sub) -> std::function<int()> {
       auto args = std::make_shared<BatchArgs>();
       const BatchApps apps = add_batch_options(sub, *args);
       return [=, &sub]() -> int {
         if (apps.plan_sweep->parsed()) {
           args->plan.flags.duration_given = apps.duration->count() > 0;
           args->plan.flags.resolution_given = apps.resolution->count() > 0;
           args->plan.flags.seeds_given = apps.seeds->count() > 0;
           return plan_sweep_cmd(args->plan);
         }
         if (apps.plan_verify->parsed()) return plan_verify_cmd(args->plan);
         if (apps.plan_golden->parsed()) return plan_golden_cmd(args->plan);
         if (apps.run->parsed()) return run_cmd(args->task);
         if (apps.merge->parsed()) return merge_cmd(args->task);
         if (apps.status->parsed()) return status_cmd(args->task);
         if (apps.local->parsed()) return local_cmd(args->local);
         if (apps.slurm->parsed()) {
           if (args->slurm.wait) args->slurm.submit = true;
           return slurm_cmd(args->slurm);
         }
         std::cerr << sub.help();
         return 2;
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
