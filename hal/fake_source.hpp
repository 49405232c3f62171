#pragma once
// An in-memory EventSource for tests: yields the events it was given, sorted into the
// contract order, optionally failing at a chosen index.
#include <optional>
#include <vector>

#include "hal/event_source.hpp"

namespace orthosonar::hal {

class FakeSource final : public EventSource {
 public:
  // Events are sorted by event_before(); sequences are kept as given.
  explicit FakeSource(std::vector<Event> events, std::optional<size_t> fail_at = std::nullopt);
  Pulled next() override;
  std::string describe() const override { return "fake"; }

 private:
  std::vector<Event> events_;
  size_t index_ = 0;
  std::optional<size_t> fail_at_;
};

// Assigns per-channel sequence numbers (0, 1, ...) in stamp order, then sorts.
std::vector<Event> make_events(const std::vector<Payload>& payloads);

}  // namespace orthosonar::hal
