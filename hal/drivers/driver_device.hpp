#pragma once
// One live device behind the hal::Device interface: a TCP (or serial) link, its decoder and,
// for an Oculus, the UDP status listener (discovery with address "auto", part number).
// Not thread-safe; DeviceLink runs one per thread with reconnects.
#include <memory>

#include "hal/device.hpp"
#include "hal/drivers/decoders.hpp"
#include "hal/drivers/socket.hpp"

namespace orthosonar::hal::drivers {

class DriverDevice final : public Device {
 public:
  DriverDevice(DeviceConfig config, ReconnectPolicy policy);
  // Opens the link (discovering the address from status messages when "auto") and sends the
  // greeting (Oculus SimpleFire). A fresh decoder starts with every connection.
  Status connect() override;
  // Oculus: range_m, gain_percent, gamma, mode, fire_version; resends the fire message.
  Status configure(const std::vector<std::pair<std::string, std::string>>& settings) override;
  // Payloads decoded from the bytes waiting now (stamps unset: the queue stamps at receipt).
  // An Error when the link closed or failed; the caller reconnects.
  Result<std::vector<Payload>> read() override;
  DeviceHealth health() const override;
  std::string name() const override { return config_.name; }

  void disconnect();
  // Binds the Oculus status listener (done by connect() too); a no-op for other devices.
  Status listen_status() { return open_status(); }
  bool connected() const { return link_.valid(); }
  // Waits until the link or the status socket is readable (or the timeout passes).
  void wait(Millis timeout) const;
  // The UDP port the status listener is bound to (0 when none).
  uint16_t status_port() const { return status_.valid() ? local_port(status_) : 0; }
  uint16_t part_number() const { return decoder_ ? decoder_->part_number() : config_.part_number; }
  const DeviceConfig& config() const { return config_; }

 private:
  void drain_status();
  Status open_status();
  DeviceConfig config_;
  ReconnectPolicy policy_;
  Fd link_;
  Fd status_;
  std::unique_ptr<Decoder> decoder_;
  std::string discovered_address_;
  bool status_seen_ = false;
  Bytes last_status_;
  DeviceHealth health_;
  uint64_t malformed_before_ = 0;  // from previous connections
  uint64_t ok_before_ = 0;
  uint64_t gaps_before_ = 0;
};

}  // namespace orthosonar::hal::drivers
