#pragma once
// The bounded queue between the driver threads and the core. Payloads are stamped here, at
// receipt, from the tool's clock (strictly increasing, so arrival order is the contract order
// of event_before()); per-channel sequence numbers are assigned when the consumer pops, so
// consumed events are numbered 0, 1, ... per channel.
//
// Overflow policy (explicit, counted): sonar pings are bounded by sonar_capacity; when a new
// ping arrives at a full queue the OLDEST queued ping is dropped (the freshest image is worth
// more). Navigation (IMU, DVL, depth) is never dropped for sonar; it is bounded only by
// nav_capacity as a memory guard, past which the oldest nav item is dropped and counted.
// Whatever the consumer pops is what the core consumed, so a recording of the popped events
// replays exactly; the drop counts go to the run's fault report.
#include <array>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>

#include "core/events.hpp"

namespace orthosonar::hal::drivers {

using Clock = std::function<Time()>;
// A monotonic clock (CLOCK_MONOTONIC) counted from the first call of the returned function.
Clock monotonic_clock_from_now();

struct QueuePolicy {
  size_t sonar_capacity = 8;
  size_t nav_capacity = 100000;
};

struct QueueStats {
  std::array<uint64_t, kChannelCount> pushed{};
  std::array<uint64_t, kChannelCount> dropped{};
  size_t max_depth = 0;
};

class LiveQueue {
 public:
  LiveQueue(Clock clock, QueuePolicy policy = {}) : clock_(std::move(clock)), policy_(policy) {}
  // Stamps `p` with the clock (strictly after the previous stamp) and enqueues it.
  void push(Payload p);
  // The next event, waiting up to `timeout`; nullopt on timeout or after close() when empty.
  std::optional<Event> pop(std::chrono::milliseconds timeout);
  void close();
  bool closed() const;
  QueueStats stats() const;
  Time now() const { return clock_(); }

 private:
  Clock clock_;
  QueuePolicy policy_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Event> q_;
  size_t sonar_in_queue_ = 0;
  Time last_stamp_ = Time::min();
  std::array<uint64_t, kChannelCount> next_seq_{};
  QueueStats stats_;
  bool closed_ = false;
};

// Stamps a payload in place (every payload type carries its stamp).
void set_stamp(Payload& p, Time t);

}  // namespace orthosonar::hal::drivers
