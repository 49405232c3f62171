#pragma once
// Pairing of horizontal and vertical pings (SPEC §4.1): each h ping is paired with the v
// ping closest in time, within max_dt; pings that find no partner are counted as
// unpaired and dropped. Feed pings in stamp order (as an EventSource delivers them).
// Not thread-safe.
#include <cstddef>
#include <deque>
#include <optional>
#include <utility>

#include "core/events.hpp"

namespace orthosonar::perception {

class PingPairer {
 public:
  explicit PingPairer(Time max_dt);
  // Accepts a ping of either mount (by ping.mount).
  void push(SonarPing ping);
  // The next ready pair (h, v), in stamp order of the h ping, or nothing yet.
  std::optional<std::pair<SonarPing, SonarPing>> pop();
  // End of stream: resolves every pending ping (pairs become ready, the rest unpaired).
  void flush();
  size_t unpaired_h() const { return unpaired_h_; }
  size_t unpaired_v() const { return unpaired_v_; }
  size_t pairs() const { return pairs_; }
  // The oldest h ping still held (waiting for a partner or to be popped): a pair made later
  // is stamped at or after it. nullopt when none is held.
  std::optional<Time> oldest_h() const;
  int64_t memory_bytes() const;  // the pings waiting for a partner or to be popped (core/memory.hpp)

 private:
  void resolve(bool final);
  Time max_dt_;
  std::deque<SonarPing> h_, v_;
  std::deque<std::pair<SonarPing, SonarPing>> ready_;
  Time latest_;
  bool seen_any_ = false;
  size_t unpaired_h_ = 0, unpaired_v_ = 0, pairs_ = 0;
};

}  // namespace orthosonar::perception
