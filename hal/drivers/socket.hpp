#pragma once
// Minimal POSIX sockets and serial ports for the drivers and emulators (IPv4, blocking fds
// with poll() timeouts). Everything returns errors as values; SIGPIPE is never raised.
#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include "core/result.hpp"

namespace orthosonar::hal::drivers {

// An owned file descriptor.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  Fd(Fd&& o) noexcept : fd_(o.release()) {}
  Fd& operator=(Fd&& o) noexcept;
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() { reset(); }
  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int release() {
    const int f = fd_;
    fd_ = -1;
    return f;
  }
  void reset();

 private:
  int fd_ = -1;
};

using Millis = std::chrono::milliseconds;

// Listening TCP socket on address:port (port 0 picks an ephemeral port; see local_port()).
Result<Fd> tcp_listen(const std::string& address, uint16_t port);
// Accepts one client, waiting at most `timeout`; an invalid Fd on timeout.
Result<Fd> tcp_accept(const Fd& listener, Millis timeout);
Result<Fd> tcp_connect(const std::string& address, uint16_t port, Millis timeout);
Result<Fd> udp_bind(const std::string& address, uint16_t port);
Result<Fd> udp_socket();
Status udp_send_to(const Fd& fd, const std::string& address, uint16_t port, std::span<const uint8_t> bytes);
uint16_t local_port(const Fd& fd);
// Opens a serial device raw (8N1, no flow control) at `baud` (e.g. 115200).
Result<Fd> open_serial(const std::string& path, int baud);

// True when fd is readable within `timeout` (or has hung up).
bool wait_readable(const Fd& fd, Millis timeout);
// Reads what is available: the byte count, 0 at end of stream, or an error.
Result<size_t> read_some(const Fd& fd, std::span<uint8_t> buf);
// One datagram (non-blocking: 0 bytes when none is waiting); `from_ip` gets the sender address.
Result<size_t> recv_datagram(const Fd& fd, std::span<uint8_t> buf, std::string* from_ip);
Status write_all(const Fd& fd, std::span<const uint8_t> bytes, Millis timeout);

}  // namespace orthosonar::hal::drivers
