#pragma once
// Renders sonar pings ahead of the consumer on worker threads. Each ping is a pure function
// of (mount, index), so the bytes are the same for any thread count; only the wall time
// changes. Jobs run in consumption order (h0, v0, h1, v1, ...) within a bounded window.
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {

class PingPrefetch {
 public:
  using RenderFn = std::function<SonarRender(SonarMount, uint64_t)>;
  PingPrefetch(int threads, uint64_t count_h, uint64_t count_v, RenderFn render);
  ~PingPrefetch();
  PingPrefetch(const PingPrefetch&) = delete;
  PingPrefetch& operator=(const PingPrefetch&) = delete;
  // Blocks until the ping is rendered. Pings must be taken in job order. An exception
  // thrown by the render function on a worker thread is rethrown here.
  SonarRender take(SonarMount mount, uint64_t index);

 private:
  void work();
  RenderFn render_;
  std::vector<std::pair<SonarMount, uint64_t>> jobs_;
  std::map<std::pair<int, uint64_t>, uint64_t> job_of_;
  std::mutex mu_;
  std::condition_variable cv_;
  uint64_t next_job_ = 0;
  uint64_t taken_ = 0;
  uint64_t window_ = 4;
  bool stop_ = false;
  std::map<uint64_t, SonarRender> done_;
  std::map<uint64_t, std::exception_ptr> failed_;
  std::vector<std::thread> workers_;
};

}  // namespace orthosonar::sim
