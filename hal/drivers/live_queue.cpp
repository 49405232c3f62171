#include "hal/drivers/live_queue.hpp"

#include <chrono>

namespace orthosonar::hal::drivers {
namespace {
bool is_sonar(Channel c) { return c == Channel::kSonarHorizontal || c == Channel::kSonarVertical; }
}  // namespace

Clock monotonic_clock_from_now() {
  const auto origin = std::chrono::steady_clock::now();
  return [origin] {
    return Time::from_ns(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - origin).count());
  };
}

void set_stamp(Payload& p, Time t) {
  std::visit([t](auto& v) { v.stamp = t; }, p);
}

void LiveQueue::push(Payload p) {
  {
    std::lock_guard lock(mu_);
    if (closed_) return;
    Time t = clock_();
    if (last_stamp_ != Time::min() && t <= last_stamp_) t = last_stamp_ + Time::from_ns(1);
    last_stamp_ = t;
    set_stamp(p, t);
    const Channel c = channel_of(p);
    ++stats_.pushed[static_cast<size_t>(c)];
    const bool sonar = is_sonar(c);
    const size_t nav_in_queue = q_.size() - sonar_in_queue_;
    if ((sonar && sonar_in_queue_ >= policy_.sonar_capacity) || (!sonar && nav_in_queue >= policy_.nav_capacity)) {
      // Drop the oldest queued item of the same class.
      for (auto it = q_.begin(); it != q_.end(); ++it) {
        if (is_sonar(it->channel) == sonar) {
          ++stats_.dropped[static_cast<size_t>(it->channel)];
          q_.erase(it);
          if (sonar) --sonar_in_queue_;
          break;
        }
      }
    }
    if (sonar && policy_.sonar_capacity == 0) {
      ++stats_.dropped[static_cast<size_t>(c)];
      return;
    }
    q_.push_back(Event{t, c, 0, std::move(p)});
    if (sonar) ++sonar_in_queue_;
    if (q_.size() > stats_.max_depth) stats_.max_depth = q_.size();
  }
  cv_.notify_one();
}

std::optional<Event> LiveQueue::pop(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mu_);
  cv_.wait_for(lock, timeout, [&] { return !q_.empty() || closed_; });
  if (q_.empty()) return std::nullopt;
  Event e = std::move(q_.front());
  q_.pop_front();
  if (is_sonar(e.channel)) --sonar_in_queue_;
  e.sequence = next_seq_[static_cast<size_t>(e.channel)]++;
  return e;
}

void LiveQueue::close() {
  {
    std::lock_guard lock(mu_);
    closed_ = true;
  }
  cv_.notify_all();
}

bool LiveQueue::closed() const {
  std::lock_guard lock(mu_);
  return closed_;
}

QueueStats LiveQueue::stats() const {
  std::lock_guard lock(mu_);
  return stats_;
}

}  // namespace orthosonar::hal::drivers
