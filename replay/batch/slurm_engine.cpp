// The Slurm engine: sbatch scripts, submission and following the jobs (see slurm_engine.hpp).
#include "replay/batch/slurm_engine.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "replay/batch/process.hpp"

namespace orthosonar::batch {

namespace fs = std::filesystem;

namespace {

std::string sbatch_header(const EngineOptions& o, const std::string& job_name) {
  std::ostringstream s;
  s << "#!/bin/bash\n#SBATCH --job-name=" << job_name << "\n";
  if (!o.slurm.partition.empty()) s << "#SBATCH --partition=" << o.slurm.partition << "\n";
  if (!o.slurm.time_limit.empty()) s << "#SBATCH --time=" << o.slurm.time_limit << "\n";
  std::stringstream ss(o.slurm.extra);
  for (std::string line; std::getline(ss, line, ';');)
    if (!line.empty()) s << "#SBATCH " << line << "\n";
  return s.str();
}

Result<std::string> sbatch(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), args.begin(), args.end());
  auto c = run_captured(argv);
  if (!c.ok()) return Error{c.error().message + " (is Slurm's client installed and on PATH?)"};
  return job_id_from_sbatch(c->out, c->exit_code);
}

// "JobID|State|ExitCode" lines (fields right-trimmed); other lines are skipped.
std::vector<JobState> split_states(const std::string& out) {
  std::vector<JobState> states;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    if (std::count(line.begin(), line.end(), '|') != 2) continue;
    std::string f[3];
    size_t b = 0;
    for (int k = 0; k < 3; ++k) {
      const size_t e = k < 2 ? line.find('|', b) : std::string::npos;
      f[k] = line.substr(b, e == std::string::npos ? std::string::npos : e - b);
      while (!f[k].empty() && f[k].back() == ' ') f[k].pop_back();
      if (e == std::string::npos) break;
      b = e + 1;
    }
    states.push_back({f[0], f[1], f[2]});
  }
  return states;
}

// sacct where accounting is on; else squeue with -t all, which keeps finished jobs for
// MinJobAge.
std::vector<JobState> job_states(const std::string& id) {
  if (auto c = run_captured({"sacct", "-j", id, "-X", "-n", "-P", "-o", "JobID,State,ExitCode"});
      c.ok() && c->exit_code == 0) {
    auto states = parse_sacct(c->out);
    if (!states.empty()) return states;
  }
  if (auto c = run_captured({"squeue", "-h", "-r", "-t", "all", "-j", id, "-O", "JobArrayID:|,State:|,exit_code"});
      c.ok() && c->exit_code == 0)
    return parse_squeue(c->out);
  return {};
}

}  // namespace

SbatchScripts sbatch_scripts(const Plan& plan, const EngineOptions& o, const std::string& executable) {
  const std::string exe = shell_quote(executable);
  const std::string pdir = shell_quote(plan.dir);
  std::ostringstream arr;
  arr << sbatch_header(o, "orthosonar-" + plan.kind) << "#SBATCH --array=0-" << plan.tasks.size() - 1;
  if (o.slurm.max_parallel > 0) arr << "%" << o.slurm.max_parallel;
  arr << "\n#SBATCH --cpus-per-task=" << std::max(1, o.threads) << "\n#SBATCH --output="
      << (fs::path(plan.dir) / "logs" / "task-%a.log").string() << "\n#SBATCH --open-mode=append\n"
      << "# Written by `orthosonar batch slurm`: one array index per task of the plan; a failed\n"
      << "# task is retried " << o.retries << " time(s) in place, every attempt appended to its log.\n"
      << "set -u\nretries=" << o.retries << "\n"
      << "for attempt in $(seq 1 $((retries + 1))); do\n"
      << "  echo \"[orthosonar batch slurm] task ${SLURM_ARRAY_TASK_ID} attempt ${attempt} job ${SLURM_JOB_ID} on "
         "$(hostname) at $(date -u +%FT%TZ)\"\n"
      << "  " << exe << " batch run " << pdir << " --attempt \"$attempt\" --threads \"${SLURM_CPUS_PER_TASK:-1}\" && exit 0\n"
      << "  echo \"[orthosonar batch slurm] task ${SLURM_ARRAY_TASK_ID} attempt ${attempt} failed with exit code $?\"\n"
      << "done\nexit 2\n";
  std::ostringstream mer;
  mer << sbatch_header(o, "orthosonar-merge") << "#SBATCH --cpus-per-task=1\n#SBATCH --output="
      << (fs::path(plan.dir) / "logs" / "merge.log").string() << "\n"
      << "# Runs after the whole array (afterany): merges what is there and names what is missing.\n"
      << "exec " << exe << " batch merge " << pdir
      << (o.merge.out_dir.empty() ? "" : " -o " + shell_quote(o.merge.out_dir))
      << (o.allow_incomplete ? " --allow-incomplete" : "") << "\n";
  return {arr.str(), mer.str()};
}

Result<std::string> job_id_from_sbatch(const std::string& printed, int exit_code) {
  std::string out = printed;
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  if (exit_code != 0) return Error{"sbatch exited " + std::to_string(exit_code) + ": " + out};
  const auto nl = out.find_last_of('\n');  // warnings may come first
  std::string id = nl == std::string::npos ? out : out.substr(nl + 1);
  id = id.substr(0, id.find(';'));  // "jobid;cluster"
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    return Error{"sbatch printed '" + out + "', not a job id"};
  return id;
}

std::vector<JobState> parse_sacct(const std::string& out) { return split_states(out); }

std::vector<JobState> parse_squeue(const std::string& out) {
  auto states = split_states(out);
  for (auto& s : states) {
    const long raw = std::atol(s.exit_code.c_str());
    s.exit_code = std::to_string(raw >> 8) + ":" + std::to_string(raw & 127);
  }
  return states;
}

std::string states_summary(const std::vector<JobState>& states) {
  if (states.empty()) return "state unknown (neither sacct nor squeue knows the job any more)";
  std::map<std::string, int> n;
  std::set<std::string> codes;
  for (const auto& s : states) {
    ++n[s.state];
    if (s.exit_code != "0:0") codes.insert(s.exit_code);
  }
  std::string out;
  for (const auto& [state, count] : n) out += (out.empty() ? "" : ", ") + state + " " + std::to_string(count);
  for (const auto& c : codes) out += " (exit " + c + ")";
  return out;
}

SlurmEngine::SlurmEngine(EngineOptions options)
    : options_(std::move(options)), executable_(task_executable(options_)) {}

Result<std::pair<std::string, std::string>> SlurmEngine::write_scripts(const Plan& plan) {
  if (plan.tasks.empty()) return Error{"the plan has no tasks"};
  const fs::path dir = fs::path(plan.dir) / "slurm";
  std::error_code ec;
  fs::create_directories(dir, ec);
  fs::create_directories(fs::path(plan.dir) / "logs", ec);
  if (ec) return Error{"cannot create '" + dir.string() + "': " + ec.message()};
  const SbatchScripts s = sbatch_scripts(plan, options_, executable_);
  const fs::path array_path = dir / "array.sbatch", merge_path = dir / "merge.sbatch";
  for (const auto& [p, text] : {std::pair{array_path, s.array}, std::pair{merge_path, s.merge}}) {
    std::ofstream f(p, std::ios::trunc);
    f << text;
    if (!f) return Error{"cannot write '" + p.string() + "'"};
    fs::permissions(p, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec, fs::perm_options::add, ec);
  }
  plan_ = plan;
  scripts_ = std::make_pair(array_path.string(), merge_path.string());
  return *scripts_;
}

Status SlurmEngine::submit(const Plan& plan) {
  if (!scripts_ || !plan_ || plan_->dir != plan.dir)
    if (auto s = write_scripts(plan); !s.ok()) return s.error();
  earlier_failures_.clear();
  for (const auto& t : plan.tasks)
    if (const auto stamp = failure_time(plan, t.index)) earlier_failures_[t.index] = *stamp;
  auto array_id = sbatch({scripts_->first});
  if (!array_id.ok()) return array_id.error();
  auto merge_id = sbatch({"--dependency=afterany:" + *array_id, scripts_->second});
  if (!merge_id.ok())
    return Error{"array " + *array_id + " submitted, but the merge job not: " + merge_id.error().message};
  array_job_ = *array_id;
  merge_job_ = *merge_id;
  std::ofstream f(fs::path(plan.dir) / "slurm" / "jobs.json", std::ios::trunc);
  f << nlohmann::json{{"array", array_job_}, {"merge", merge_job_}}.dump(2) << "\n";
  return {};
}

Result<int> SlurmEngine::wait() {
  if (!plan_ || array_job_.empty()) return Error{"nothing submitted"};
  const Plan& plan = *plan_;
  std::ostream& log = *options_.log;
  const auto t0 = std::chrono::steady_clock::now();
  std::set<size_t> reported_failures;
  std::string last_line;
  for (;;) {
    auto q = run_captured({"squeue", "-h", "-j", array_job_ + "," + merge_job_, "-o", "%i %T"});
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
        const auto stamp = failure_time(plan, t.index);
        const auto before = earlier_failures_.find(t.index);
        if (stamp && before != earlier_failures_.end() && *stamp == before->second) continue;  // an earlier submission's
        ++failed;
        if (reported_failures.insert(t.index).second)
          log << "batch slurm: task " << t.index << " (" << t.name << ") failed: " << st.detail << "; log "
              << log_path(plan, t.index) << "\n";
      }
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream line;
    line << "batch slurm: " << done << "/" << plan.tasks.size() << " tasks done, " << failed << " failed; jobs "
         << running << " running, " << pending << " pending";
    if (line.str() != last_line) {
      log << line.str() << " (" << static_cast<int>(elapsed) << " s)\n";
      last_line = line.str();
    }
    if (!any) break;
    if (options_.slurm.timeout_s > 0 && elapsed > options_.slurm.timeout_s) {
      std::ostringstream m;
      m << "--timeout " << options_.slurm.timeout_s << " s reached; jobs " << array_job_ << " and " << merge_job_
        << " are still queued (scancel them, or follow with squeue)";
      return Error{m.str()};
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.slurm.poll_s));
  }
  const auto merge_states = job_states(merge_job_);
  log << "batch slurm: array job " << array_job_ << ": " << states_summary(job_states(array_job_)) << "; merge job "
      << merge_job_ << ": " << states_summary(merge_states) << "; merge log "
      << (fs::path(plan.dir) / "logs" / "merge.log").string() << "\n";
  {
    std::ifstream merge_log(fs::path(plan.dir) / "logs" / "merge.log");
    if (merge_log) *options_.merge.out << merge_log.rdbuf();
  }
  if (merge_states.empty()) return 2;
  if (merge_states.front().state != "COMPLETED") {
    const int code = std::atoi(merge_states.front().exit_code.c_str());
    return code > 0 ? code : 2;
  }
  return 0;
}

}  // namespace orthosonar::batch
