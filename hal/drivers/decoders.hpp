#pragma once
// Per-protocol decoders: bytes in, event payloads out (stamps are set later, at receipt, by
// the LiveQueue). Malformed input is counted and skipped.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "hal/drivers/device_config.hpp"

namespace orthosonar::hal::drivers {

class Decoder {
 public:
  virtual ~Decoder() = default;
  virtual void push(std::span<const uint8_t> bytes, std::vector<Payload>& out) = 0;
  virtual uint64_t messages() const = 0;
  virtual uint64_t malformed() const = 0;
  virtual std::string last_error() const = 0;
  // Discontinuities of the device's own packet counter (DSP-1760); 0 for devices without one.
  virtual uint64_t sequence_gaps() const { return 0; }
  // Bytes to send right after connecting (the Oculus SimpleFire message), empty otherwise.
  virtual Bytes greeting() const { return {}; }
  // A status datagram (Oculus UDP 52102); false when it is not a valid status message.
  virtual bool on_status(std::span<const uint8_t>) { return false; }
  virtual uint16_t part_number() const { return 0; }
};

std::unique_ptr<Decoder> make_decoder(const DeviceConfig& config);

}  // namespace orthosonar::hal::drivers
