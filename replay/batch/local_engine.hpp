#pragma once
// The local engine (engine.hpp): every task of a plan as a child process on this machine,
// `jobs` at a time, a failed task retried up to `retries` times (every attempt appended to
// its log), then the merge in-process.
#include <sys/types.h>

#include <chrono>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "replay/batch/engine.hpp"

namespace orthosonar::batch {

class LocalEngine final : public Engine {
 public:
  explicit LocalEngine(EngineOptions options);
  std::string name() const override { return "local"; }
  Status submit(const Plan& plan) override;
  Result<int> wait() override;

 private:
  struct Running {
    size_t index = 0;
    int attempt = 1;
    std::chrono::steady_clock::time_point started;
  };
  Status start_queued();  // starts queued tasks while fewer than `jobs` run

  EngineOptions options_;
  std::string executable_;
  std::optional<Plan> plan_;
  std::deque<std::pair<size_t, int>> queue_;  // task, attempt
  std::map<pid_t, Running> running_;
  std::vector<size_t> failed_;
  size_t done_ = 0;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace orthosonar::batch
