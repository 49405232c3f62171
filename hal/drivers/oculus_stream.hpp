#pragma once
// Oculus byte-stream framing (TCP 52100 delivers concatenated messages, possibly split or
// preceded by garbage) and the conversion of decoded pings to core SonarPing events.
#include <deque>
#include <optional>
#include <string>

#include "core/events.hpp"
#include "hal/drivers/oculus_protocol.hpp"

namespace orthosonar::hal::drivers::oculus {

struct StreamStats {
  uint64_t messages = 0;        // complete, well-formed messages returned
  uint64_t malformed = 0;       // frames that failed validation (skipped)
  uint64_t garbage_bytes = 0;   // bytes discarded while searching for the 0x4F53 id
};

// Feed bytes with push(); pop() returns decoded messages in order. After garbage or a frame
// that fails validation the parser resynchronises on the next 0x4F53 id.
class StreamParser {
 public:
  void push(std::span<const uint8_t> bytes);
  // The next decoded message, or nullopt when more bytes are needed. Malformed frames are
  // counted in stats() and skipped; last_error() names the latest one.
  std::optional<Message> pop();
  const StreamStats& stats() const { return stats_; }
  const std::string& last_error() const { return last_error_; }
  size_t buffered() const { return buf_.size() - start_; }

 private:
  void compact();
  Bytes buf_;
  size_t start_ = 0;
  StreamStats stats_;
  std::string last_error_;
};

// A decoded ping as a core event payload. Bearings from the ping's table (1/100 degree) to
// radians; the part number comes from the status message or the configuration. The device
// orders beams port to starboard with bearings growing to starboard; SonarPing bearings grow
// to the left (h) / up (v) (REP-103), so columns are mirrored and bearings negated.
Result<SonarPing> to_sonar_ping(const PingResult& ping, SonarMount mount, uint16_t part_number, Time stamp);

// The ping result a device would send for `ping` (emulator side). Bearings are rounded to
// 1/100 degree; `version` selects SimplePingResult V1 or V2.
PingResult ping_result_from(const SonarPing& ping, int version, uint16_t src_device_id);

}  // namespace orthosonar::hal::drivers::oculus
