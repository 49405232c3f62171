#include "hal/sim/ping_prefetch.hpp"

namespace orthosonar::sim {

PingPrefetch::PingPrefetch(int threads, uint64_t count_h, uint64_t count_v, RenderFn render)
    : render_(std::move(render)), window_(static_cast<uint64_t>(3 * threads)) {
  for (uint64_t i = 0; i < std::max(count_h, count_v); ++i) {
    if (i < count_h) jobs_.emplace_back(SonarMount::kHorizontal, i);
    if (i < count_v) jobs_.emplace_back(SonarMount::kVertical, i);
  }
  for (uint64_t j = 0; j < jobs_.size(); ++j) job_of_[{static_cast<int>(jobs_[j].first), jobs_[j].second}] = j;
  for (int t = 0; t < threads; ++t) workers_.emplace_back([this] { work(); });
}

PingPrefetch::~PingPrefetch() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  for (auto& w : workers_) w.join();
}

void PingPrefetch::work() {
  while (true) {
    uint64_t job = 0;
    {
      std::unique_lock lock(mu_);
      cv_.wait(lock, [this] { return stop_ || (next_job_ < jobs_.size() && next_job_ < taken_ + window_); });
      if (stop_) return;
      job = next_job_++;
    }
    // A render that throws (e.g. out of memory) must not end the process from a worker
    // thread: the exception is handed to the consumer, which rethrows it from take().
    std::optional<SonarRender> r;
    std::exception_ptr fault;
    try {
      r = render_(jobs_[job].first, jobs_[job].second);
    } catch (...) {
      fault = std::current_exception();
    }
    {
      std::lock_guard lock(mu_);
      if (fault) failed_.emplace(job, fault);
      else done_.emplace(job, std::move(*r));
    }
    cv_.notify_all();
  }
}

SonarRender PingPrefetch::take(SonarMount mount, uint64_t index) {
  const auto it = job_of_.find({static_cast<int>(mount), index});
  if (it == job_of_.end()) return render_(mount, index);
  const uint64_t job = it->second;
  std::unique_lock lock(mu_);
  cv_.wait(lock, [&] { return done_.count(job) > 0 || failed_.count(job) > 0; });
  if (const auto f = failed_.find(job); f != failed_.end()) {
    const std::exception_ptr fault = f->second;
    failed_.erase(f);
    taken_ = std::max(taken_, job + 1);
    lock.unlock();
    cv_.notify_all();
    std::rethrow_exception(fault);
  }
  SonarRender r = std::move(done_.at(job));
  done_.erase(job);
  taken_ = std::max(taken_, job + 1);
  lock.unlock();
  cv_.notify_all();
  return r;
}

}  // namespace orthosonar::sim
