#pragma once
// Interface of a live device driver (sonar, IMU, DVL, depth). Drivers own their sockets
// and threads; they turn bytes into event payloads stamped by the tool's clock, never the
// core's (the core has none).
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::hal {

struct DeviceHealth {
  bool connected = false;
  uint64_t messages_ok = 0;
  uint64_t messages_malformed = 0;   // counted and skipped, never fatal
  uint64_t sequence_gaps = 0;        // breaks in the device's own packet counter (DSP-1760), 0 without one
  uint64_t reconnects = 0;
  std::string last_error;
};

class Device {
 public:
  virtual ~Device() = default;
  virtual Status connect() = 0;
  // Device-specific settings as key/value text (range_m, gain_percent, ...).
  virtual Status configure(const std::vector<std::pair<std::string, std::string>>& settings) = 0;
  // Payloads decoded since the last call (non-blocking); an Error when the link failed.
  virtual Result<std::vector<Payload>> read() = 0;
  virtual DeviceHealth health() const = 0;
  virtual std::string name() const = 0;
};

}  // namespace orthosonar::hal
