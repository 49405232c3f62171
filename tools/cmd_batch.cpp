// `orthosonar batch`: work sharded into independent tasks that any engine can run
// (docs/BATCH.md; the plan folder is described in tools/support_batch.hpp).
//
//   batch plan sweep --scenes a,b --seeds 1-5 [--cells ...] [--cells-per-task K] -o plan/
//   batch plan verify DIR|FIXTURE.mcap|LIST.txt... -o plan/
//   batch plan golden [S.yaml...] [--no-images] -o plan/
//   batch run plan/ [--task I]        one task (index from --task, $SLURM_ARRAY_TASK_ID or
//                                     $JOB_COMPLETION_INDEX); skipped when its result is current
//   batch merge plan/ [-o DIR]        the one-machine command's outputs (+ JUnit XML)
//   batch status plan/                each task's state
//   batch local plan/ -j N            every task on this machine, retried, then merged
//   batch slurm plan/ [--partition P] [--cpus-per-task C] [--max-parallel K] [--submit] [--wait]
//                                     a Slurm job array and a dependent merge job
#include <algorithm>
#include <array>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "replay/run/mission.hpp"
#include "replay/run/sweep.hpp"
#include "tools/cli.hpp"
#include "tools/support_batch.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_process.hpp"

namespace orthosonar::cli {
namespace {

namespace fs = std::filesystem;
using namespace batch;  // NOLINT: this file is the batch front end

int batch_fail(const std::string& what, const std::string& m) {
  std::cerr << "orthosonar batch " << what << ": " << m << "\n";
  return 2;
}

// An option's file, or nothing when the option was not given.
Result<std::string> read_file_text(const std::string& path) {
  if (path.empty()) return std::string();
  return read_text(path);
}

int default_threads() {
  if (const char* c = std::getenv("SLURM_CPUS_PER_TASK"); c && std::atoi(c) > 0) return std::atoi(c);
  return 1;
}

// ---------------------------------------------------------------- plan

struct PlanArgs {
  std::string out = "plan";
  bool replace = false;
  // sweep
  std::string scenes = "marina1,marina2,harbor,aircraft";
  std::string seeds = "1-5";
  std::string cells = "all";
  int cells_per_task = 0;
  double duration_s = 600.0;
  std::string resolution = "full";
  std::string sim_config, run_config;
  bool duration_given = false, resolution_given = false, seeds_given = false;  // flags actually given
  std::string systems = "fusion,submap";
  std::string model;
  bool no_report = false;
  // verify
  std::vector<std::string> inputs;
  std::string verify_systems;
  // golden
  std::vector<std::string> scenarios;
  bool no_images = false;
};

int finish_plan(Result<Plan> plan, bool replace) {
  if (!plan.ok()) return batch_fail("plan", plan.error().message);
  if (Status s = write_plan(*plan, replace); !s.ok()) return batch_fail("plan", s.error().message);
  std::cout << "plan: " << plan->kind << ", " << plan->tasks.size() << " tasks in " << plan->dir << "\n";
  for (const auto& t : plan->tasks) std::cout << "  " << t.index << " " << t.name << "\n";
  std::cout << "run: orthosonar batch local " << plan->dir << " -j N, or orthosonar batch slurm " << plan->dir
            << " --submit --wait\n";
  return 0;
}

int plan_sweep_cmd(const PlanArgs& a) {
  SweepPlanSpec s;
  std::stringstream ss(a.scenes);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) s.scenes.push_back(item);
  auto seeds = run::parse_seeds(a.seeds);
  if (!seeds.ok()) return batch_fail("plan", "--" + seeds.error().message);
  s.cells = a.cells;
  s.cells_per_task = a.cells_per_task;
  auto sim = read_file_text(a.sim_config);
  if (!sim.ok()) return batch_fail("plan", "--sim-config: " + sim.error().message);
  // A flag given wins over --sim-config, the file over the flag's default (as sweep, simulate).
  run::MissionFlags flags;
  flags.duration_s = a.duration_s;
  flags.duration_given = a.duration_given;
  flags.resolution = a.resolution;
  flags.resolution_given = a.resolution_given;
  flags.seeds = *seeds;
  flags.seeds_given = a.seeds_given;
  if (Status st = run::resolve_mission_flags(*sim, flags); !st.ok())
    return batch_fail("plan", "--sim-config " + a.sim_config + ": " + st.error().message);
  s.seeds = flags.seeds;
  s.duration_s = flags.duration_s;
  s.resolution = flags.resolution;
  auto cfg = read_file_text(a.run_config);
  if (!cfg.ok()) return batch_fail("plan", "--config: " + cfg.error().message);
  s.sim_config_yaml = *sim;
  s.run_config_yaml = *cfg;
  s.systems = a.systems;
  s.model_path = a.model;
  s.report = !a.no_report;
  return finish_plan(plan_sweep(s, a.out), a.replace);
}

int plan_verify_cmd(const PlanArgs& a) {
  VerifyPlanSpec s;
  s.inputs = a.inputs;
  auto cfg = read_file_text(a.run_config);
  if (!cfg.ok()) return batch_fail("plan", "--config: " + cfg.error().message);
  s.run_config_yaml = *cfg;
  s.systems = a.verify_systems;
  return finish_plan(plan_verify(s, a.out), a.replace);
}

int plan_golden_cmd(const PlanArgs& a) {
  GoldenPlanSpec s;
  s.scenarios = a.scenarios;
  s.images = !a.no_images;
  return finish_plan(plan_golden(s, a.out), a.replace);
}

// ---------------------------------------------------------------- run, merge, status

struct BatchRunArgs {
  std::string plan;
  long task = -1;
  int threads = 0;
  int attempt = 1;
  bool force = false;
  std::string out;
};

int run_cmd(const BatchRunArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("run", plan.error().message);
  auto index = task_index(*plan, a.task >= 0 ? std::optional<long>(a.task) : std::nullopt);
  if (!index.ok()) return batch_fail("run", index.error().message);
  RunTaskOptions o;
  o.threads = a.threads > 0 ? a.threads : default_threads();
  o.attempt = a.attempt;
  o.force = a.force;
  return run_task(*plan, *index, o);
}

int merge_cmd(const BatchRunArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("merge", plan.error().message);
  return merge(*plan, a.out);
}

int status_cmd(const BatchRunArgs& a) {
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

// ---------------------------------------------------------------- local engine

struct LocalArgs {
  std::string plan;
  int jobs = 2;
  int threads = 1;
  int retries = 2;
  bool no_merge = false;
  std::string out;
};

int local_cmd(const LocalArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("local", plan.error().message);
  const int jobs = std::max(1, a.jobs);
  const std::string exe = self_executable();
  std::deque<std::pair<size_t, int>> queue;  // task, attempt
  for (const auto& t : plan->tasks) queue.emplace_back(t.index, 1);
  std::map<pid_t, std::tuple<size_t, int, std::chrono::steady_clock::time_point>> running;
  std::vector<size_t> failed;
  size_t done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (!queue.empty() || !running.empty()) {
    while (static_cast<int>(running.size()) < jobs && !queue.empty()) {
      const auto [index, attempt] = queue.front();
      queue.pop_front();
      const std::string log = log_path(*plan, index);
      {
        std::ofstream(log, std::ios::app) << "[orthosonar batch local] task " << index << " attempt " << attempt << "\n";
      }
      auto pid = spawn_logged({exe, "batch", "run", plan->dir, "--task", std::to_string(index), "--attempt",
                               std::to_string(attempt), "--threads", std::to_string(std::max(1, a.threads))},
                              log);
      if (!pid.ok()) return batch_fail("local", pid.error().message);
      running[*pid] = {index, attempt, std::chrono::steady_clock::now()};
    }
    const auto [pid, code] = wait_any();
    if (pid < 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const auto [index, attempt, started] = it->second;
    running.erase(it);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const std::string name = "task " + std::to_string(index) + " (" + plan->tasks[index].name + ")";
    if (code == 0) {
      ++done;
      std::cerr << "batch local: [" << done << "/" << plan->tasks.size() << "] " << name << " done in "
                << static_cast<int>(s) << " s\n";
    } else if (attempt <= a.retries) {
      std::cerr << "batch local: " << name << " attempt " << attempt << " failed (exit " << code << "), retrying; log "
                << log_path(*plan, index) << "\n";
      queue.emplace_back(index, attempt + 1);
    } else {
      failed.push_back(index);
      const TaskStatus st = task_status(*plan, plan->tasks[index], false);
      std::cerr << "batch local: " << name << " FAILED after " << attempt << " attempt(s): " << st.detail << "; log "
                << log_path(*plan, index) << "\n";
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cerr << "batch local: " << done << " of " << plan->tasks.size() << " tasks done, " << failed.size()
            << " failed, in " << static_cast<int>(wall + 0.5) << " s wall on " << jobs << " worker(s)\n";
  if (a.no_merge) return failed.empty() ? 0 : 2;
  return merge(*plan, a.out);
}

// ---------------------------------------------------------------- Slurm engine

struct SlurmArgs {
  std::string plan;
  std::string partition;
  int cpus_per_task = 1;
  int max_parallel = 0;
  int retries = 2;
  std::string time_limit;
  std::string extra;  // extra #SBATCH lines, ';'-separated
  bool submit = false;
  bool wait = false;
  double timeout_s = 0.0;
  double poll_s = 2.0;
  std::string out;
};

std::string sbatch_header(const SlurmArgs& a, const std::string& job_name) {
  std::ostringstream s;
  s << "#!/bin/bash\n#SBATCH --job-name=" << job_name << "\n";
  if (!a.partition.empty()) s << "#SBATCH --partition=" << a.partition << "\n";
  if (!a.time_limit.empty()) s << "#SBATCH --time=" << a.time_limit << "\n";
  std::stringstream ss(a.extra);
  for (std::string line; std::getline(ss, line, ';');)
    if (!line.empty()) s << "#SBATCH " << line << "\n";
  return s.str();
}

Result<std::pair<std::string, std::string>> write_sbatch(const Plan& plan, const SlurmArgs& a) {
  const fs::path dir = fs::path(plan.dir) / "slurm";
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::create_directories(fs::path(plan.dir) / "logs", ec);
  if (ec) return Error{"cannot create '" + dir.string() + "': " + ec.message()};
  const std::string exe = shell_quote(self_executable());
  const std::string pdir = shell_quote(plan.dir);
  std::ostringstream arr;
  arr << sbatch_header(a, "orthosonar-" + plan.kind) << "#SBATCH --array=0-" << plan.tasks.size() - 1;
  if (a.max_parallel > 0) arr << "%" << a.max_parallel;
  arr << "\n#SBATCH --cpus-per-task=" << std::max(1, a.cpus_per_task) << "\n#SBATCH --output="
      << (fs::path(plan.dir) / "logs" / "task-%a.log").string() << "\n#SBATCH --open-mode=append\n"
      << "# Written by `orthosonar batch slurm`: one array index per task of the plan; a failed\n"
      << "# task is retried " << a.retries << " time(s) in place, every attempt appended to its log.\n"
      << "set -u\nretries=" << a.retries << "\n"
      << "for attempt in $(seq 1 $((retries + 1))); do\n"
      << "  echo \"[orthosonar batch slurm] task ${SLURM_ARRAY_TASK_ID} attempt ${attempt} job ${SLURM_JOB_ID} on "
         "$(hostname) at $(date -u +%FT%TZ)\"\n"
      << "  " << exe << " batch run " << pdir << " --attempt \"$attempt\" --threads \"${SLURM_CPUS_PER_TASK:-1}\" && exit 0\n"
      << "  echo \"[orthosonar batch slurm] task ${SLURM_ARRAY_TASK_ID} attempt ${attempt} failed with exit code $?\"\n"
      << "done\nexit 2\n";
  std::ostringstream mer;
  mer << sbatch_header(a, "orthosonar-merge") << "#SBATCH --cpus-per-task=1\n#SBATCH --output="
      << (fs::path(plan.dir) / "logs" / "merge.log").string() << "\n"
      << "# Runs after the whole array (afterany): merges what is there and names what is missing.\n"
      << "exec " << exe << " batch merge " << pdir << (a.out.empty() ? "" : " -o " + shell_quote(a.out))
      << (allow_incomplete() ? " --allow-incomplete" : "") << "\n";
  const fs::path array_path = dir / "array.sbatch", merge_path = dir / "merge.sbatch";
  for (const auto& [p, text] : {std::pair{array_path, arr.str()}, std::pair{merge_path, mer.str()}}) {
    std::ofstream f(p, std::ios::trunc);
    f << text;
    if (!f) return Error{"cannot write '" + p.string() + "'"};
    fs::permissions(p, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add, ec);
  }
  return std::make_pair(array_path.string(), merge_path.string());
}

Result<std::string> sbatch(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), args.begin(), args.end());
  auto c = run_captured(argv);
  if (!c.ok()) return Error{c.error().message + " (is Slurm's client installed and on PATH?)"};
  std::string out = c->out;
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  if (c->exit_code != 0) return Error{"sbatch exited " + std::to_string(c->exit_code) + ": " + out};
  const auto nl = out.find_last_of('\n');  // warnings may come first
  std::string id = nl == std::string::npos ? out : out.substr(nl + 1);
  id = id.substr(0, id.find(';'));  // "jobid;cluster"
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    return Error{"sbatch printed '" + out + "', not a job id"};
  return id;
}

// One line per job (or array task): "JobID|State|ExitCode". sacct where accounting is on;
// else squeue with -t all, which keeps finished jobs for MinJobAge (its exit_code is the
// raw wait status: code = value >> 8).
std::vector<std::array<std::string, 3>> job_states(const std::string& id) {
  std::vector<std::array<std::string, 3>> out;
  auto split = [](const std::string& line) {
    std::array<std::string, 3> f;
    size_t b = 0;
    for (int k = 0; k < 3; ++k) {
      const size_t e = k < 2 ? line.find('|', b) : std::string::npos;
      f[k] = line.substr(b, e == std::string::npos ? std::string::npos : e - b);
      while (!f[k].empty() && f[k].back() == ' ') f[k].pop_back();
      if (e == std::string::npos) break;
      b = e + 1;
    }
    return f;
  };
  if (auto c = run_captured({"sacct", "-j", id, "-X", "-n", "-P", "-o", "JobID,State,ExitCode"});
      c.ok() && c->exit_code == 0) {
    std::istringstream lines(c->out);
    for (std::string line; std::getline(lines, line);)
      if (std::count(line.begin(), line.end(), '|') == 2) out.push_back(split(line));
    if (!out.empty()) return out;
  }
  if (auto c = run_captured({"squeue", "-h", "-r", "-t", "all", "-j", id, "-O", "JobArrayID:|,State:|,exit_code"});
      c.ok() && c->exit_code == 0) {
    std::istringstream lines(c->out);
    for (std::string line; std::getline(lines, line);)
      if (std::count(line.begin(), line.end(), '|') == 2) {
        auto f = split(line);
        const long raw = std::atol(f[2].c_str());
        f[2] = std::to_string(raw >> 8) + ":" + std::to_string(raw & 127);
        out.push_back(f);
      }
  }
  return out;
}

// "COMPLETED 7, FAILED 1 (exit 2:0)" for a job or an array.
std::string states_summary(const std::vector<std::array<std::string, 3>>& states) {
  if (states.empty()) return "state unknown (neither sacct nor squeue knows the job any more)";
  std::map<std::string, int> n;
  std::set<std::string> codes;
  for (const auto& s : states) {
    ++n[s[1]];
    if (s[2] != "0:0") codes.insert(s[2]);
  }
  std::string out;
  for (const auto& [state, count] : n) out += (out.empty() ? "" : ", ") + state + " " + std::to_string(count);
  for (const auto& c : codes) out += " (exit " + c + ")";
  return out;
}

// failed.json's modification time per task (absent: none), to tell this submission's
// failures from those left by an earlier one.
std::map<size_t, fs::file_time_type> failure_stamps(const Plan& plan) {
  std::map<size_t, fs::file_time_type> out;
  for (const auto& t : plan.tasks) {
    std::error_code ec;
    const auto stamp = fs::last_write_time(fs::path(result_dir(plan, t.index)) / "failed.json", ec);
    if (!ec) out[t.index] = stamp;
  }
  return out;
}

int follow(const Plan& plan, const std::string& array_id, const std::string& merge_id, const SlurmArgs& a,
           const std::map<size_t, fs::file_time_type>& earlier_failures) {
  const auto t0 = std::chrono::steady_clock::now();
  std::set<size_t> reported_failures;
  std::string last_line;
  for (;;) {
    auto q = run_captured({"squeue", "-h", "-j", array_id + "," + merge_id, "-o", "%i %T"});
    int pending = 0, running = 0;
    bool any = false;
    if (q.ok() && q->exit_code == 0) {
      std::istringstream lines(q->out);
      for (std::string line; std::getline(lines, line);) {
        if (line.empty()) continue;
        any = true;
        if (line.find("RUNNING") != std::string::npos || line.find("COMPLETING") != std::string::npos) ++running;
        else if (line.find("PENDING") != std::string::npos) ++pending;
      }
    }
    size_t done = 0, failed = 0;
    for (const auto& t : plan.tasks) {
      const TaskStatus st = task_status(plan, t, false);
      if (st.state == TaskState::kDone) ++done;
      if (st.state == TaskState::kFailed) {
        std::error_code ec;
        const auto stamp = fs::last_write_time(fs::path(result_dir(plan, t.index)) / "failed.json", ec);
        const auto before = earlier_failures.find(t.index);
        if (!ec && before != earlier_failures.end() && stamp == before->second) continue;  // an earlier submission's
        ++failed;
        if (reported_failures.insert(t.index).second)
          std::cerr << "batch slurm: task " << t.index << " (" << t.name << ") failed: " << st.detail << "; log "
                    << log_path(plan, t.index) << "\n";
      }
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream line;
    line << "batch slurm: " << done << "/" << plan.tasks.size() << " tasks done, " << failed << " failed; jobs "
         << running << " running, " << pending << " pending";
    if (line.str() != last_line) {
      std::cerr << line.str() << " (" << static_cast<int>(elapsed) << " s)\n";
      last_line = line.str();
    }
    if (!any) break;
    if (a.timeout_s > 0 && elapsed > a.timeout_s) {
      std::cerr << "orthosonar batch slurm: --timeout " << a.timeout_s << " s reached; jobs " << array_id << " and "
                << merge_id << " are still queued (scancel them, or follow with squeue)\n";
      return 2;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(a.poll_s));
  }
  const auto merge_states = job_states(merge_id);
  std::cerr << "batch slurm: array job " << array_id << ": " << states_summary(job_states(array_id)) << "; merge job "
            << merge_id << ": " << states_summary(merge_states) << "; merge log "
            << (fs::path(plan.dir) / "logs" / "merge.log").string() << "\n";
  {
    std::ifstream log(fs::path(plan.dir) / "logs" / "merge.log");
    if (log) std::cout << log.rdbuf();
  }
  if (merge_states.empty()) return 2;
  if (merge_states.front()[1] != "COMPLETED") {
    const int code = std::atoi(merge_states.front()[2].c_str());
    return code > 0 ? code : 2;
  }
  return 0;
}

int slurm_cmd(const SlurmArgs& a) {
  auto plan = load_plan(a.plan);
  if (!plan.ok()) return batch_fail("slurm", plan.error().message);
  if (plan->tasks.empty()) return batch_fail("slurm", "the plan has no tasks");
  auto scripts = write_sbatch(*plan, a);
  if (!scripts.ok()) return batch_fail("slurm", scripts.error().message);
  std::cout << "slurm: job array " << scripts->first << " (" << plan->tasks.size() << " tasks), merge "
            << scripts->second << "\n";
  if (!a.submit) {
    std::cout << "submit: id=$(sbatch --parsable " << scripts->first << ") && sbatch --dependency=afterany:$id "
              << scripts->second << "   (or rerun with --submit [--wait])\n";
    return 0;
  }
  const auto earlier_failures = failure_stamps(*plan);
  auto array_id = sbatch({scripts->first});
  if (!array_id.ok()) return batch_fail("slurm", array_id.error().message);
  auto merge_id = sbatch({"--dependency=afterany:" + *array_id, scripts->second});
  if (!merge_id.ok()) return batch_fail("slurm", "array " + *array_id + " submitted, but the merge job not: " + merge_id.error().message);
  {
    std::ofstream f(fs::path(plan->dir) / "slurm" / "jobs.json", std::ios::trunc);
    f << nlohmann::json{{"array", *array_id}, {"merge", *merge_id}}.dump(2) << "\n";
  }
  std::cout << "slurm: submitted array job " << *array_id << " and merge job " << *merge_id << "\n";
  if (!a.wait) return 0;
  return follow(*plan, *array_id, *merge_id, a, earlier_failures);
}

// ---------------------------------------------------------------- registration

const bool registered_batch = register_command(
    {"batch", "Shard work into independent tasks: plan, run, merge; run them locally or as a Slurm job array",
     [](CLI::App& sub) -> std::function<int()> {
       sub.require_subcommand(1);
       auto pa = std::make_shared<PlanArgs>();
       auto* plan = sub.add_subcommand("plan", "Write a plan: a manifest of independent tasks");
       plan->require_subcommand(1);
       auto common_plan = [pa](CLI::App* p) {
         p->add_option("-o,--out", pa->out, "Plan folder")->required();
         p->add_flag("--replace", pa->replace, "Replace another plan (and its results) in that folder");
       };
       auto* ps = plan->add_subcommand("sweep", "Scenes x seeds x keyframe cells x systems (the seed study)");
       common_plan(ps);
       ps->add_option("--scenes", pa->scenes, "Built-in scenes, comma-separated")->capture_default_str();
       auto* ps_seeds = ps->add_option("--seeds", pa->seeds, "Seeds: 1-5, 1,3,7 or 2 (overrides --sim-config)")
                            ->capture_default_str();
       ps->add_option("--cells", pa->cells, "all, or DISTANCE/ROTATION list such as 1/30,3/30")->capture_default_str();
       ps->add_option("--cells-per-task", pa->cells_per_task, "Cells per task (0: a whole scene/seed per task)")
           ->capture_default_str();
       auto* ps_duration = ps->add_option("--duration", pa->duration_s, "Mission duration (s; overrides --sim-config)")
                               ->capture_default_str();
       auto* ps_resolution = ps->add_option("--resolution", pa->resolution, "full or reduced (overrides --sim-config)")
                                 ->capture_default_str();
       ps->add_option("--sim-config", pa->sim_config, "Simulator config YAML");
       ps->add_option("--config", pa->run_config, "Run config YAML (docs/CONFIG.md)");
       ps->add_option("--systems", pa->systems, "Mapping systems")->capture_default_str();
       ps->add_option("--model", pa->model, "Classifier model for the inference systems");
       ps->add_flag("--no-report", pa->no_report, "No reference-cell outputs and report per scene/seed");
       auto* pv = plan->add_subcommand("verify", "Fixtures with expected digests (a regression suite)");
       common_plan(pv);
       pv->add_option("inputs", pa->inputs,
                      "Fixtures (X.mcap with X.digest.json beside it), folders of them, or lists "
                      "('FIXTURE EXPECTED' per line)")
           ->required();
       pv->add_option("--config", pa->run_config, "Run config YAML");
       pv->add_option("--systems", pa->verify_systems, "Mapping systems (default: those each expected digest names)");
       auto* pg = plan->add_subcommand("golden", "The golden scenarios");
       common_plan(pg);
       pg->add_option("scenarios", pa->scenarios, "Scenario files (default: golden/scenarios/*.yaml)");
       pg->add_flag("--no-images", pa->no_images, "Skip the rendered-image checks (no X display on the nodes)");

       auto ra = std::make_shared<BatchRunArgs>();
       auto* run = sub.add_subcommand("run", "Run one task of a plan");
       run->add_option("plan", ra->plan, "Plan folder")->required();
       run->add_option("--task", ra->task, "Task index (default: $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX)");
       run->add_option("--threads", ra->threads, "Threads (default: $SLURM_CPUS_PER_TASK, else 1)");
       run->add_option("--attempt", ra->attempt, "Attempt number (recorded; set by the engines)");
       run->add_flag("--force", ra->force, "Run even when the result is current");
       auto* merge_app = sub.add_subcommand("merge", "Gather the results into the one-machine outputs");
       merge_app->add_option("plan", ra->plan, "Plan folder")->required();
       merge_app->add_option("-o,--out", ra->out, "Output folder (default: <plan>/merged)");
       add_allow_incomplete_flag(*merge_app);
       auto* status = sub.add_subcommand("status", "Each task's state (exit 0 when all are done)");
       status->add_option("plan", ra->plan, "Plan folder")->required();

       auto la = std::make_shared<LocalArgs>();
       auto* local = sub.add_subcommand("local", "Run every task on this machine, then merge");
       local->add_option("plan", la->plan, "Plan folder")->required();
       local->add_option("-j,--jobs", la->jobs, "Tasks at once")->capture_default_str();
       local->add_option("--threads", la->threads, "Threads per task")->capture_default_str();
       local->add_option("--retries", la->retries, "Retries of a failed task")->capture_default_str();
       local->add_flag("--no-merge", la->no_merge, "Do not merge afterwards");
       local->add_option("-o,--out", la->out, "Merge output folder (default: <plan>/merged)");
       add_allow_incomplete_flag(*local);

       auto sa = std::make_shared<SlurmArgs>();
       auto* slurm = sub.add_subcommand("slurm", "Write (and submit) a Slurm job array and a dependent merge job");
       slurm->add_option("plan", sa->plan, "Plan folder (on a file system the nodes share)")->required();
       slurm->add_option("--partition", sa->partition, "Slurm partition");
       slurm->add_option("--cpus-per-task", sa->cpus_per_task, "CPUs (threads) per task")->capture_default_str();
       slurm->add_option("--max-parallel", sa->max_parallel, "At most K tasks at once (%K throttle; 0: no limit)");
       slurm->add_option("--retries", sa->retries, "Retries of a failed task")->capture_default_str();
       slurm->add_option("--time", sa->time_limit, "Time limit per task (sbatch --time)");
       slurm->add_option("--sbatch", sa->extra, "Extra #SBATCH lines, ';'-separated (e.g. '--mem=4G;--account=x')");
       slurm->add_flag("--submit", sa->submit, "Submit with sbatch");
       slurm->add_flag("--wait", sa->wait, "Follow the jobs (squeue/sacct) until the merge has run");
       slurm->add_option("--timeout", sa->timeout_s, "With --wait: give up after S seconds (0: never)");
       slurm->add_option("--poll", sa->poll_s, "With --wait: seconds between polls")->capture_default_str();
       slurm->add_option("-o,--out", sa->out, "Merge output folder (default: <plan>/merged)");
       add_allow_incomplete_flag(*slurm);

       return [=, &sub]() -> int {
         if (ps->parsed()) {
           pa->duration_given = ps_duration->count() > 0;
           pa->resolution_given = ps_resolution->count() > 0;
           pa->seeds_given = ps_seeds->count() > 0;
           return plan_sweep_cmd(*pa);
         }
         if (pv->parsed()) return plan_verify_cmd(*pa);
         if (pg->parsed()) return plan_golden_cmd(*pa);
         if (run->parsed()) return run_cmd(*ra);
         if (merge_app->parsed()) return merge_cmd(*ra);
         if (status->parsed()) return status_cmd(*ra);
         if (local->parsed()) return local_cmd(*la);
         if (slurm->parsed()) {
           if (sa->wait) sa->submit = true;
           return slurm_cmd(*sa);
         }
         std::cerr << sub.help();
         return 2;
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
