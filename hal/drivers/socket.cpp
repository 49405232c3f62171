#include "hal/drivers/socket.hpp"

#include <arpa/inet.h>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

namespace orthosonar::hal::drivers {
namespace {

Error sys_error(const std::string& what) { return Error{what + ": " + std::strerror(errno)}; }

Result<sockaddr_in> make_addr(const std::string& address, uint16_t port) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  if (inet_pton(AF_INET, address.c_str(), &a.sin_addr) != 1) return Error{"bad IPv4 address '" + address + "'"};
  return a;
}

int poll_for(int fd, short events, Millis timeout) {
  pollfd p{fd, events, 0};
  int r;
  do {
    r = ::poll(&p, 1, static_cast<int>(timeout.count()));
  } while (r < 0 && errno == EINTR);
  return r > 0 ? p.revents : r;
}

}  // namespace

Fd& Fd::operator=(Fd&& o) noexcept {
  if (this != &o) {
    reset();
    fd_ = o.release();
  }
  return *this;
}

void Fd::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Result<Fd> tcp_listen(const std::string& address, uint16_t port) {
  auto a = make_addr(address, port);
  if (!a) return a.error();
  Fd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd.valid()) return sys_error("socket");
  const int one = 1;
  ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&*a), sizeof(sockaddr_in)) != 0)
    return sys_error("bind " + address + ":" + std::to_string(port));
  if (::listen(fd.get(), 4) != 0) return sys_error("listen");
  return fd;
}

Result<Fd> tcp_accept(const Fd& listener, Millis timeout) {
  const int r = poll_for(listener.get(), POLLIN, timeout);
  if (r < 0) return sys_error("poll");
  if (r == 0) return Fd();
  Fd fd(::accept4(listener.get(), nullptr, nullptr, SOCK_CLOEXEC));
  if (!fd.valid()) return sys_error("accept");
  const int one = 1;
  ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

Result<Fd> tcp_connect(const std::string& address, uint16_t port, Millis timeout) {
  auto a = make_addr(address, port);
  if (!a) return a.error();
  Fd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
  if (!fd.valid()) return sys_error("socket");
  const std::string where = address + ":" + std::to_string(port);
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&*a), sizeof(sockaddr_in)) != 0) {
    if (errno != EINPROGRESS) return sys_error("connect " + where);
    const int r = poll_for(fd.get(), POLLOUT, timeout);
    if (r <= 0) return Error{"connect " + where + ": timed out"};
    int soerr = 0;
    socklen_t len = sizeof soerr;
    ::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &soerr, &len);
    if (soerr != 0) {
      errno = soerr;
      return sys_error("connect " + where);
    }
  }
  const int flags = ::fcntl(fd.get(), F_GETFL);
  ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
  const int one = 1;
  ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

Result<Fd> udp_socket() {
  Fd fd(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!fd.valid()) return sys_error("socket");
  const int one = 1;
  ::setsockopt(fd.get(), SOL_SOCKET, SO_BROADCAST, &one, sizeof one);
  return fd;
}

Result<Fd> udp_bind(const std::string& address, uint16_t port) {
  auto a = make_addr(address, port);
  if (!a) return a.error();
  auto fd = udp_socket();
  if (!fd) return fd.error();
  const int one = 1;
  ::setsockopt(fd->get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(fd->get(), reinterpret_cast<const sockaddr*>(&*a), sizeof(sockaddr_in)) != 0)
    return sys_error("bind udp " + address + ":" + std::to_string(port));
  return std::move(*fd);
}

Status udp_send_to(const Fd& fd, const std::string& address, uint16_t port, std::span<const uint8_t> bytes) {
  auto a = make_addr(address, port);
  if (!a) return a.error();
  const ssize_t n = ::sendto(fd.get(), bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&*a), sizeof(sockaddr_in));
  if (n < 0 || static_cast<size_t>(n) != bytes.size()) return sys_error("sendto");
  return Status::Ok();
}

uint16_t local_port(const Fd& fd) {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&a), &len) != 0) return 0;
  return ntohs(a.sin_port);
}

Result<Fd> open_serial(const std::string& path, int baud) {
  Fd fd(::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
  if (!fd.valid()) return sys_error("open " + path);
  termios t{};
  if (::tcgetattr(fd.get(), &t) != 0) return sys_error("tcgetattr " + path);
  ::cfmakeraw(&t);
  speed_t speed;
  switch (baud) {
    case 9600: speed = B9600; break;
    case 19200: speed = B19200; break;
    case 38400: speed = B38400; break;
    case 57600: speed = B57600; break;
    case 115200: speed = B115200; break;
    case 230400: speed = B230400; break;
    case 460800: speed = B460800; break;
    case 921600: speed = B921600; break;
    default: return Error{"unsupported baud rate " + std::to_string(baud)};
  }
  ::cfsetispeed(&t, speed);
  ::cfsetospeed(&t, speed);
  t.c_cflag |= CLOCAL | CREAD;
  t.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
  t.c_cc[VMIN] = 0;
  t.c_cc[VTIME] = 0;
  if (::tcsetattr(fd.get(), TCSANOW, &t) != 0) return sys_error("tcsetattr " + path);
  return fd;
}

bool wait_readable(const Fd& fd, Millis timeout) { return poll_for(fd.get(), POLLIN, timeout) > 0; }

Result<size_t> read_some(const Fd& fd, std::span<uint8_t> buf) {
  ssize_t n;
  do {
    n = ::read(fd.get(), buf.data(), buf.size());
  } while (n < 0 && errno == EINTR);
  if (n < 0) return sys_error("read");
  return static_cast<size_t>(n);
}

Result<size_t> recv_datagram(const Fd& fd, std::span<uint8_t> buf, std::string* from_ip) {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  const ssize_t n = ::recvfrom(fd.get(), buf.data(), buf.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&a), &len);
  if (n < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return size_t{0};
    return sys_error("recvfrom");
  }
  if (from_ip) {
    char ip[INET_ADDRSTRLEN] = {};
    ::inet_ntop(AF_INET, &a.sin_addr, ip, sizeof ip);
    *from_ip = ip;
  }
  return static_cast<size_t>(n);
}

Status write_all(const Fd& fd, std::span<const uint8_t> bytes, Millis timeout) {
  size_t done = 0;
  while (done < bytes.size()) {
    const int r = poll_for(fd.get(), POLLOUT, timeout);
    if (r <= 0) return Error{"write: timed out"};
    if (r & (POLLERR | POLLHUP)) return Error{"write: peer closed"};
    ssize_t n = ::send(fd.get(), bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL);
    if (n < 0 && errno == ENOTSOCK) n = ::write(fd.get(), bytes.data() + done, bytes.size() - done);  // serial
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      return sys_error("write");
    }
    done += static_cast<size_t>(n);
  }
  return Status::Ok();
}

}  // namespace orthosonar::hal::drivers
