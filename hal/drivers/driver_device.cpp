#include "hal/drivers/driver_device.hpp"

#include <array>
#include <poll.h>

namespace orthosonar::hal::drivers {

DriverDevice::DriverDevice(DeviceConfig config, ReconnectPolicy policy)
    : config_(std::move(config)), policy_(policy), decoder_(make_decoder(config_)) {}

Status DriverDevice::open_status() {
  if (config_.kind != DeviceKind::kOculus || !config_.listen_status || status_.valid()) return Status::Ok();
  // Status broadcasts arrive on every interface; bind the wildcard address.
  // Loopback devices (tests, emulators) listen on loopback only; real ones on every interface.
  const std::string bind_address = config_.address.rfind("127.", 0) == 0 ? config_.address : "0.0.0.0";
  auto fd = udp_bind(bind_address, config_.status_port);
  if (!fd) return fd.error();
  status_ = std::move(*fd);
  return Status::Ok();
}

void DriverDevice::drain_status() {
  if (!status_.valid()) return;
  std::array<uint8_t, 2048> buf;
  for (int i = 0; i < 64; ++i) {
    std::string from;
    auto n = recv_datagram(status_, buf, &from);
    if (!n || *n == 0) return;
    if (decoder_->on_status(std::span<const uint8_t>(buf.data(), *n))) {
      status_seen_ = true;
      last_status_.assign(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(*n));
      if (config_.address == "auto") discovered_address_ = from;
    } else {
      ++health_.messages_malformed;
    }
  }
}

Status DriverDevice::connect() {
  disconnect();
  if (decoder_) {
    ok_before_ += decoder_->messages();
    malformed_before_ += decoder_->malformed();
    gaps_before_ += decoder_->sequence_gaps();
  }
  decoder_ = make_decoder(config_);
  if (status_seen_) (void)decoder_->on_status(last_status_);  // keep the learned part number
  if (auto s = open_status(); !s.ok()) {
    // A busy status port must not stop the data link; note it.
    health_.last_error = s.error().message;
  }
  const Millis timeout(policy_.connect_timeout_ms);
  if (config_.kind == DeviceKind::kOculus && config_.part_number == 0) {
    // The part number comes from the status broadcast: wait for one before taking pings.
    if (!status_.valid()) return Error{config_.name + ": part_number 0 needs the status listener"};
    if (!status_seen_ && wait_readable(status_, timeout)) drain_status();
    if (!status_seen_) return Error{config_.name + ": no status message yet (part number unknown)"};
  }
  if (!config_.serial_path.empty()) {
    auto fd = open_serial(config_.serial_path, config_.baud);
    if (!fd) return fd.error();
    link_ = std::move(*fd);
  } else {
    std::string address = config_.address;
    if (address == "auto") {
      if (!status_.valid()) return Error{config_.name + ": discovery needs the status listener"};
      if (discovered_address_.empty() && wait_readable(status_, timeout)) drain_status();
      if (discovered_address_.empty()) return Error{config_.name + ": no status message received for discovery"};
      address = discovered_address_;
    }
    auto fd = tcp_connect(address, config_.port, timeout);
    if (!fd) return Error{config_.name + ": " + fd.error().message};
    link_ = std::move(*fd);
  }
  const Bytes hello = decoder_->greeting();
  if (!hello.empty()) {
    if (auto s = write_all(link_, hello, timeout); !s.ok()) {
      link_.reset();
      return Error{config_.name + ": sending the fire message: " + s.error().message};
    }
  }
  health_.connected = true;
  return Status::Ok();
}

Status DriverDevice::configure(const std::vector<std::pair<std::string, std::string>>& settings) {
  for (const auto& [k, v] : settings) {
    double x = 0;
    try {
      x = std::stod(v);
    } catch (...) {
      return Error{config_.name + ": setting '" + k + "' needs a number, got '" + v + "'"};
    }
    if (config_.kind != DeviceKind::kOculus) return Error{config_.name + ": no setting '" + k + "'"};
    if (k == "range_m") config_.fire.range = x;
    else if (k == "gain_percent") config_.fire.gain_percent = x;
    else if (k == "gamma") config_.fire.gamma = static_cast<uint8_t>(x);
    else if (k == "mode") config_.fire.master_mode = static_cast<uint8_t>(x);
    else if (k == "fire_version") config_.fire_version = x == 1.0 ? 1 : 2;
    else return Error{config_.name + ": unknown setting '" + k + "'"};
  }
  if (config_.kind == DeviceKind::kOculus && link_.valid()) {
    const Bytes fire = oculus::encode_fire(config_.fire, config_.fire_version, 0, 0);
    return write_all(link_, fire, Millis(policy_.connect_timeout_ms));
  }
  return Status::Ok();
}

Result<std::vector<Payload>> DriverDevice::read() {
  std::vector<Payload> out;
  drain_status();
  if (!link_.valid()) return Error{config_.name + ": not connected"};
  std::array<uint8_t, 65536> buf;
  for (int i = 0; i < 16; ++i) {
    if (!wait_readable(link_, Millis(0))) break;
    auto n = read_some(link_, buf);
    if (!n) {
      disconnect();
      return Error{config_.name + ": " + n.error().message};
    }
    if (*n == 0) {
      decoder_->push({}, out);
      disconnect();
      if (!out.empty()) return out;  // deliver what arrived before the close; the next read reports it
      return Error{config_.name + ": connection closed by the device"};
    }
    decoder_->push(std::span<const uint8_t>(buf.data(), *n), out);
  }
  return out;
}

void DriverDevice::wait(Millis timeout) const {
  std::array<pollfd, 2> p{};
  int n = 0;
  if (link_.valid()) p[static_cast<size_t>(n++)] = pollfd{link_.get(), POLLIN, 0};
  if (status_.valid()) p[static_cast<size_t>(n++)] = pollfd{status_.get(), POLLIN, 0};
  ::poll(p.data(), static_cast<nfds_t>(n), static_cast<int>(timeout.count()));
}

void DriverDevice::disconnect() {
  link_.reset();
  health_.connected = false;
}

DeviceHealth DriverDevice::health() const {
  DeviceHealth h = health_;
  h.messages_ok = ok_before_ + (decoder_ ? decoder_->messages() : 0);
  h.messages_malformed += malformed_before_ + (decoder_ ? decoder_->malformed() : 0);
  h.sequence_gaps = gaps_before_ + (decoder_ ? decoder_->sequence_gaps() : 0);
  if (decoder_ && !decoder_->last_error().empty()) h.last_error = decoder_->last_error();
  return h;
}

}  // namespace orthosonar::hal::drivers
