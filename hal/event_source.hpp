#pragma once
// Where events come from: a live driver set, the simulator, or a recorded fixture.
// A pull API so the consumer (the core pipeline) sets the pace; errors are values.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::hal {

// What next() returns: an event, the end of the stream, or an error.
struct Pulled {
  std::optional<Event> event;   // set when an event was produced
  bool end_of_stream = false;   // true once the source is exhausted
  std::optional<Error> error;   // a fault; the source may or may not continue (see source docs)

  static Pulled of(Event e) { return {std::move(e), false, std::nullopt}; }
  static Pulled end() { return {std::nullopt, true, std::nullopt}; }
  static Pulled fail(Error e) { return {std::nullopt, false, std::move(e)}; }
};

// Contract: events come out in the order of event_before() (stamp, channel, sequence);
// a source that cannot guarantee that reports an error instead of a silent reorder.
// Not thread-safe: one consumer.
class EventSource {
 public:
  virtual ~EventSource() = default;
  virtual Pulled next() = 0;
  // A short human-readable name, e.g. "fixture:h.mcap" or "sim:harbor".
  virtual std::string describe() const = 0;
  // Heap bytes of the events the source holds decoded and not yet yielded (read-ahead,
  // reordering), for memory reports (issue 41); 0 when it holds none or does not say.
  // Called from the thread that calls next().
  virtual int64_t buffered_bytes() const { return 0; }
};

}  // namespace orthosonar::hal
