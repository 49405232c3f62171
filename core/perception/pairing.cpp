#include "core/perception/pairing.hpp"

#include "core/memory.hpp"

#include <algorithm>

namespace orthosonar::perception {

PingPairer::PingPairer(Time max_dt) : max_dt_(max_dt) {}

void PingPairer::push(SonarPing ping) {
  if (!seen_any_ || ping.stamp > latest_) latest_ = ping.stamp;
  seen_any_ = true;
  // Keep each queue in stamp order even if a source delivers equal stamps out of order.
  auto& q = ping.mount == SonarMount::kHorizontal ? h_ : v_;
  auto it = std::upper_bound(q.begin(), q.end(), ping.stamp,
                             [](Time t, const SonarPing& p) { return t < p.stamp; });
  q.insert(it, std::move(ping));
  resolve(false);
}

std::optional<std::pair<SonarPing, SonarPing>> PingPairer::pop() {
  if (ready_.empty()) return std::nullopt;
  auto out = std::move(ready_.front());
  ready_.pop_front();
  return out;
}

void PingPairer::flush() { resolve(true); }

// The oldest pending h ping is decided once no future v ping can be within max_dt of it
// (stream time has passed stamp + max_dt) or at the end of the stream. It takes the
// pending v ping closest in time (ties: the earlier v). v pings too old for every
// pending and future h ping are unpaired. Greedy in h order; at 5 Hz with max_dt half
// the period a v ping is within reach of at most one h ping, so greedy is optimal there.
void PingPairer::resolve(bool final) {
  for (;;) {
    const Time horizon = h_.empty() ? latest_ : h_.front().stamp;
    while (!v_.empty() && (v_.front().stamp < horizon - max_dt_ || (final && h_.empty()))) {
      v_.pop_front();
      ++unpaired_v_;
    }
    if (h_.empty()) return;
    const Time th = h_.front().stamp;
    if (!final && !(latest_ > th + max_dt_)) return;
    size_t best = v_.size();
    Time best_dt = Time::max();
    for (size_t i = 0; i < v_.size(); ++i) {
      const Time dt = abs(v_[i].stamp - th);
      if (dt <= max_dt_ && dt < best_dt) {
        best = i;
        best_dt = dt;
      }
    }
    if (best == v_.size()) {
      ++unpaired_h_;
    } else {
      // v pings older than the chosen one can only pair with later h pings if they are
      // within reach; they stay pending and the horizon rule above decides them.
      ready_.emplace_back(std::move(h_.front()), std::move(v_[best]));
      v_.erase(v_.begin() + static_cast<std::ptrdiff_t>(best));
      ++pairs_;
    }
    h_.pop_front();
  }
}

std::optional<Time> PingPairer::oldest_h() const {
  std::optional<Time> t;
  if (!ready_.empty()) t = ready_.front().first.stamp;
  if (!h_.empty() && (!t || h_.front().stamp < *t)) t = h_.front().stamp;
  return t;
}

int64_t PingPairer::memory_bytes() const {
  int64_t n = heap_bytes(h_) + heap_bytes(v_) + heap_bytes(ready_);
  for (const auto& p : h_) n += heap_bytes(p);
  for (const auto& p : v_) n += heap_bytes(p);
  for (const auto& [h, v] : ready_) n += heap_bytes(h) + heap_bytes(v);
  return n;
}

}  // namespace orthosonar::perception
