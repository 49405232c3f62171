// The command line of `orthosonar batch` (see support_batch_args.hpp).
#include "tools/support_batch_args.hpp"

#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {

BatchApps add_batch_options(CLI::App& sub, BatchArgs& a) {
  sub.require_subcommand(1);
  auto* plan = sub.add_subcommand("plan", "Write a plan: a manifest of independent tasks");
  plan->require_subcommand(1);
  auto common_plan = [&a](CLI::App* p) {
    p->add_option("-o,--out", a.plan.out, "Plan folder")->required();
    p->add_flag("--replace", a.plan.replace, "Replace another plan (and its results) in that folder");
  };
  auto* ps = plan->add_subcommand("sweep", "Scenes x seeds x keyframe cells x systems (the seed study)");
  common_plan(ps);
  ps->add_option("--scenes", a.plan.scenes, "Built-in scenes, comma-separated")->capture_default_str();
  auto* ps_seeds = ps->add_option("--seeds", a.plan.seeds, "Seeds: 1-5, 1,3,7 or 2 (overrides --sim-config)")
                       ->capture_default_str();
  ps->add_option("--cells", a.plan.sweep.cells, "all, or DISTANCE/ROTATION list such as 1/30,3/30")->capture_default_str();
  ps->add_option("--cells-per-task", a.plan.sweep.cells_per_task, "Cells per task (0: a whole scene/seed per task)")
      ->capture_default_str();
  auto* ps_duration = ps->add_option("--duration", a.plan.flags.duration_s, "Mission duration (s; overrides --sim-config)")
                          ->capture_default_str();
  auto* ps_resolution = ps->add_option("--resolution", a.plan.flags.resolution, "full or reduced (overrides --sim-config)")
                            ->capture_default_str();
  ps->add_option("--sim-config", a.plan.sim_config, "Simulator config YAML");
  ps->add_option("--config", a.plan.run_config, "Run config YAML (docs/CONFIG.md)");
  ps->add_option("--systems", a.plan.sweep.systems, "Mapping systems")->capture_default_str();
  ps->add_option("--model", a.plan.sweep.model_path, "Classifier model for the inference systems");
  ps->add_flag("--no-report", a.plan.no_report, "No reference-cell outputs and report per scene/seed");
  auto* pv = plan->add_subcommand("verify", "Fixtures with expected digests (a regression suite)");
  common_plan(pv);
  pv->add_option("inputs", a.plan.verify.inputs,
                 "Fixtures (X.mcap with X.digest.json beside it), folders of them, or lists "
                 "('FIXTURE EXPECTED' per line)")
      ->required();
  pv->add_option("--config", a.plan.run_config, "Run config YAML");
  pv->add_option("--systems", a.plan.verify.systems, "Mapping systems (default: those each expected digest names)");
  auto* pg = plan->add_subcommand("golden", "The golden scenarios");
  common_plan(pg);
  pg->add_option("scenarios", a.plan.golden.scenarios, "Scenario files (default: golden/scenarios/*.yaml)");
  pg->add_flag("--no-images", a.plan.no_images, "Skip the rendered-image checks (no X display on the nodes)");

  auto* run = sub.add_subcommand("run", "Run one task of a plan");
  run->add_option("plan", a.task.plan, "Plan folder")->required();
  run->add_option("--task", a.task.task, "Task index (default: $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX)");
  run->add_option("--threads", a.task.threads, "Threads (default: $SLURM_CPUS_PER_TASK, else 1)");
  run->add_option("--attempt", a.task.attempt, "Attempt number (recorded; set by the engines)");
  run->add_flag("--force", a.task.force, "Run even when the result is current");
  auto* merge_app = sub.add_subcommand("merge", "Gather the results into the one-machine outputs");
  merge_app->add_option("plan", a.task.plan, "Plan folder")->required();
  merge_app->add_option("-o,--out", a.task.out, "Output folder (default: <plan>/merged)");
  add_allow_incomplete_flag(*merge_app);
  auto* status = sub.add_subcommand("status", "Each task's state (exit 0 when all are done)");
  status->add_option("plan", a.task.plan, "Plan folder")->required();

  auto* local = sub.add_subcommand("local", "Run every task on this machine, then merge");
  local->add_option("plan", a.local.plan, "Plan folder")->required();
  local->add_option("-j,--jobs", a.local.options.local.jobs, "Tasks at once")->capture_default_str();
  local->add_option("--threads", a.local.options.threads, "Threads per task")->capture_default_str();
  local->add_option("--retries", a.local.options.retries, "Retries of a failed task")->capture_default_str();
  local->add_flag("--no-merge", a.local.no_merge, "Do not merge afterwards");
  local->add_option("-o,--out", a.local.out, "Merge output folder (default: <plan>/merged)");
  add_allow_incomplete_flag(*local);

  auto* slurm = sub.add_subcommand("slurm", "Write (and submit) a Slurm job array and a dependent merge job");
  slurm->add_option("plan", a.slurm.plan, "Plan folder (on a file system the nodes share)")->required();
  slurm->add_option("--partition", a.slurm.options.slurm.partition, "Slurm partition");
  slurm->add_option("--cpus-per-task", a.slurm.cpus_per_task, "CPUs (threads) per task")->capture_default_str();
  slurm->add_option("--max-parallel", a.slurm.options.slurm.max_parallel, "At most K tasks at once (%K throttle; 0: no limit)");
  slurm->add_option("--retries", a.slurm.options.retries, "Retries of a failed task")->capture_default_str();
  slurm->add_option("--time", a.slurm.options.slurm.time_limit, "Time limit per task (sbatch --time)");
  slurm->add_option("--sbatch", a.slurm.options.slurm.extra, "Extra #SBATCH lines, ';'-separated (e.g. '--mem=4G;--account=x')");
  slurm->add_flag("--submit", a.slurm.submit, "Submit with sbatch");
  slurm->add_flag("--wait", a.slurm.wait, "Follow the jobs (squeue/sacct) until the merge has run");
  slurm->add_option("--timeout", a.slurm.options.slurm.timeout_s, "With --wait: give up after S seconds (0: never)");
  slurm->add_option("--poll", a.slurm.options.slurm.poll_s, "With --wait: seconds between polls")->capture_default_str();
  slurm->add_option("-o,--out", a.slurm.out, "Merge output folder (default: <plan>/merged)");
  add_allow_incomplete_flag(*slurm);
  return {ps, pv, pg, run, merge_app, status, local, slurm, ps_seeds, ps_duration, ps_resolution};
}

}  // namespace orthosonar::cli
