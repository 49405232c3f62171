#include "hal/drivers/oculus_stream.hpp"

#include <cmath>
#include <numbers>

namespace orthosonar::hal::drivers::oculus {
namespace {

// A header the devices could have sent: a known message id and version. Garbage that happens
// to contain 0x4F53 rarely passes, so the parser does not wait for a bogus payload size.
bool plausible(const Header& h) {
  switch (h.msg_id) {
    case kMsgStatus: case kMsgSimpleFire: case kMsgPingResult: case kMsgSimplePingResult:
    case kMsgUserConfig: case kMsgDummy:
      break;
    default:
      return false;
  }
  return h.msg_version <= 2;
}

// For a ping result, the messageSize field must match the header once the fixed part arrived.
bool ping_size_consistent(const Header& h, std::span<const uint8_t> avail) {
  if (h.msg_id != kMsgSimplePingResult) return true;
  const size_t fixed = h.msg_version == 2 ? kPingV2Size : kPingV1Size;
  if (avail.size() < fixed) return true;  // not yet known
  ByteReader r(avail, fixed - 4);
  return r.u32() == h.message_bytes();
}

}  // namespace

void StreamParser::push(std::span<const uint8_t> bytes) {
  compact();
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void StreamParser::compact() {
  if (start_ > 0 && (start_ > 65536 || start_ == buf_.size())) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
}

std::optional<Message> StreamParser::pop() {
  for (;;) {
    // Find the id 0x4F53 ("SO" little-endian: 0x53 0x4F).
    size_t i = start_;
    while (i + 1 < buf_.size() && !(buf_[i] == 0x53 && buf_[i + 1] == 0x4F)) ++i;
    if (i + 1 >= buf_.size()) {
      // Keep a trailing 0x53 that may start the next id.
      const size_t keep = (i < buf_.size() && buf_[i] == 0x53) ? 1 : 0;
      stats_.garbage_bytes += buf_.size() - start_ - keep;
      start_ = buf_.size() - keep;
      compact();
      return std::nullopt;
    }
    stats_.garbage_bytes += i - start_;
    start_ = i;
    const std::span<const uint8_t> avail(buf_.data() + start_, buf_.size() - start_);
    if (avail.size() < kHeaderSize) return std::nullopt;
    auto header = parse_header(avail);
    if (!header || !plausible(*header) || !ping_size_consistent(*header, avail)) {
      ++stats_.malformed;
      last_error_ = header ? "oculus: implausible header (msgId " + std::to_string(header->msg_id) + ", version " +
                                 std::to_string(header->msg_version) + ")"
                           : header.error().message;
      start_ += 2;
      continue;
    }
    if (avail.size() < header->message_bytes()) return std::nullopt;
    auto msg = parse_message(avail.first(header->message_bytes()));
    if (!msg) {
      // Skip only the id: a real message may start inside the rejected frame.
      ++stats_.malformed;
      last_error_ = msg.error().message;
      start_ += 2;
      continue;
    }
    start_ += header->message_bytes();
    ++stats_.messages;
    compact();
    return std::move(*msg);
  }
}

Result<SonarPing> to_sonar_ping(const PingResult& p, SonarMount mount, uint16_t part_number, Time stamp) {
  if (p.bytes_per_pixel() > 2)
    return Error{"oculus: " + std::to_string(8 * p.bytes_per_pixel()) + "-bit images are not supported (8 or 16)"};
  if (!(p.range_resolution_m > 0.0) || !std::isfinite(p.range_resolution_m))
    return Error{"oculus: rangeResolution must be positive"};
  SonarPing s;
  s.device_id = p.header.src_device_id;
  s.part_number = part_number;
  s.mount = mount;
  s.stamp = stamp;
  s.ping_id = p.ping_id;
  s.range_resolution_m = p.range_resolution_m;
  s.frequency_hz = p.frequency_hz;
  s.gain_percent = p.fire.gain_percent;
  // The Oculus orders beams port to starboard with bearings growing to starboard; REP-103
  // bearings grow to the left (h) / up (v). Mirror the columns and negate the bearings.
  const size_t n = p.n_beams;
  const size_t bpp = static_cast<size_t>(p.bytes_per_pixel());
  s.bearings_rad.resize(n);
  for (size_t c = 0; c < n; ++c)
    s.bearings_rad[c] = -static_cast<double>(p.bearings_centideg[n - 1 - c]) / 100.0 * std::numbers::pi / 180.0;
  s.rows = p.n_ranges;
  s.cols = p.n_beams;
  s.bytes_per_pixel = static_cast<uint8_t>(bpp);
  s.image.resize(p.image.size());
  for (size_t r = 0; r < p.n_ranges; ++r)
    for (size_t c = 0; c < n; ++c)
      for (size_t k = 0; k < bpp; ++k) s.image[(r * n + c) * bpp + k] = p.image[(r * n + (n - 1 - c)) * bpp + k];
  return s;
}

PingResult ping_result_from(const SonarPing& s, int version, uint16_t src_device_id) {
  PingResult p;
  p.version = version == 2 ? 2 : 1;
  p.header.src_device_id = src_device_id;
  p.fire.master_mode = kModeLowFrequency;
  p.fire.flags = static_cast<uint8_t>(kFlagRangeAsMeters | kFlagSimpleReturn |
                                      (s.cols > 256 ? kFlag512Beams : 0) |
                                      (s.bytes_per_pixel == 2 ? kFlagData16Bit : 0));
  p.fire.range = s.rows > 0 ? s.max_range_m() : 0.0;
  p.fire.gain_percent = s.gain_percent;
  p.fire.speed_of_sound_mps = 0.0;
  p.ping_id = s.ping_id;
  p.frequency_hz = s.frequency_hz;
  p.speed_of_sound_used_mps = 1500.0;
  p.data_size = static_cast<uint8_t>(s.bytes_per_pixel == 2 ? 1 : 0);
  p.range_resolution_m = s.range_resolution_m;
  p.n_ranges = s.rows;
  p.n_beams = s.cols;
  // Inverse of to_sonar_ping(): back to the device's port-to-starboard beam order.
  const size_t n = s.cols;
  const size_t bpp = s.bytes_per_pixel == 2 ? 2 : 1;
  p.bearings_centideg.resize(n);
  for (size_t c = 0; c < n && c < s.bearings_rad.size(); ++c) {
    const double cd = std::round(-s.bearings_rad[n - 1 - c] * 180.0 / std::numbers::pi * 100.0);
    p.bearings_centideg[c] = static_cast<int16_t>(std::fmax(-32768.0, std::fmin(32767.0, cd)));
  }
  p.image.assign(s.image.size(), 0);
  for (size_t r = 0; r < s.rows; ++r)
    for (size_t c = 0; c < n; ++c)
      for (size_t k = 0; k < bpp; ++k) {
        const size_t from = (r * n + (n - 1 - c)) * bpp + k;
        if (from < s.image.size()) p.image[(r * n + c) * bpp + k] = s.image[from];
      }
  return p;
}

}  // namespace orthosonar::hal::drivers::oculus
