// The local engine: tasks as child processes on this machine, retried, then merged (see
// local_engine.hpp).
#include "replay/batch/local_engine.hpp"

#include <algorithm>
#include <fstream>

#include "replay/batch/process.hpp"
#include "replay/batch/state.hpp"

namespace orthosonar::batch {

LocalEngine::LocalEngine(EngineOptions options)
    : options_(std::move(options)), executable_(task_executable(options_)) {}

Status LocalEngine::submit(const Plan& plan) {
  plan_ = plan;
  queue_.clear();
  running_.clear();
  failed_.clear();
  done_ = 0;
  for (const auto& t : plan.tasks) queue_.emplace_back(t.index, 1);
  started_ = std::chrono::steady_clock::now();
  return start_queued();
}

Status LocalEngine::start_queued() {
  const int jobs = std::max(1, options_.local.jobs);
  while (static_cast<int>(running_.size()) < jobs && !queue_.empty()) {
    const auto [index, attempt] = queue_.front();
    queue_.pop_front();
    const std::string log = log_path(*plan_, index);
    {
      std::ofstream(log, std::ios::app) << "[orthosonar batch local] task " << index << " attempt " << attempt << "\n";
    }
    auto pid = spawn_logged({executable_, "batch", "run", plan_->dir, "--task", std::to_string(index), "--attempt",
                             std::to_string(attempt), "--threads", std::to_string(std::max(1, options_.threads))},
                            log);
    if (!pid.ok()) return pid.error();
    running_[*pid] = {index, attempt, std::chrono::steady_clock::now()};
  }
  return {};
}

Result<int> LocalEngine::wait() {
  if (!plan_) return Error{"nothing submitted"};
  const Plan& plan = *plan_;
  std::ostream& log = *options_.log;
  while (!queue_.empty() || !running_.empty()) {
    if (Status s = start_queued(); !s.ok()) return s.error();
    const auto [pid, code] = wait_any();
    if (pid < 0) break;
    const auto it = running_.find(pid);
    if (it == running_.end()) continue;
    const Running r = it->second;
    running_.erase(it);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.started).count();
    const std::string name = "task " + std::to_string(r.index) + " (" + plan.tasks[r.index].name + ")";
    if (code == 0) {
      ++done_;
      log << "batch local: [" << done_ << "/" << plan.tasks.size() << "] " << name << " done in " << static_cast<int>(s)
          << " s\n";
    } else if (r.attempt <= options_.retries) {
      log << "batch local: " << name << " attempt " << r.attempt << " failed (exit " << code << "), retrying; log "
          << log_path(plan, r.index) << "\n";
      queue_.emplace_back(r.index, r.attempt + 1);
    } else {
      failed_.push_back(r.index);
      const TaskStatus st = task_status(plan, plan.tasks[r.index], false);
      log << "batch local: " << name << " FAILED after " << r.attempt << " attempt(s): " << st.detail << "; log "
          << log_path(plan, r.index) << "\n";
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  log << "batch local: " << done_ << " of " << plan.tasks.size() << " tasks done, " << failed_.size() << " failed, in "
      << static_cast<int>(wall + 0.5) << " s wall on " << std::max(1, options_.local.jobs) << " worker(s)\n";
  if (!options_.local.merge) return failed_.empty() ? 0 : 2;
  return merge(plan, options_.merge);
}

}  // namespace orthosonar::batch
