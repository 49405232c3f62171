#include "hal/fake_source.hpp"

#include <algorithm>
#include <array>

namespace orthosonar::hal {

FakeSource::FakeSource(std::vector<Event> events, std::optional<size_t> fail_at)
    : events_(std::move(events)), fail_at_(fail_at) {
  std::stable_sort(events_.begin(), events_.end(), event_before);
}

Pulled FakeSource::next() {
  if (fail_at_ && index_ == *fail_at_) {
    fail_at_.reset();
    return Pulled::fail(Error{"fake source: injected fault at event " + std::to_string(index_)});
  }
  if (index_ >= events_.size()) return Pulled::end();
  return Pulled::of(events_[index_++]);
}

std::vector<Event> make_events(const std::vector<Payload>& payloads) {
  std::vector<Event> out;
  out.reserve(payloads.size());
  for (const auto& p : payloads) out.push_back(Event{stamp_of(p), channel_of(p), 0, p});
  std::stable_sort(out.begin(), out.end(), [](const Event& a, const Event& b) {
    return a.stamp != b.stamp ? a.stamp < b.stamp : a.channel < b.channel;
  });
  std::array<uint64_t, kChannelCount> seq{};
  for (auto& e : out) e.sequence = seq[static_cast<size_t>(e.channel)]++;
  return out;
}

}  // namespace orthosonar::hal
