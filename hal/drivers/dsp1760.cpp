#include "hal/drivers/dsp1760.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

namespace orthosonar::hal::drivers::dsp1760 {
namespace {

// CRC-32/MPEG-2, one byte at a time through a 256-entry table (MSB first: not reflected).
constexpr std::array<uint32_t, 256> make_crc_table() {
  std::array<uint32_t, 256> t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i << 24;
    for (int k = 0; k < 8; ++k) c = (c & 0x80000000u) ? (c << 1) ^ 0x04C11DB7u : c << 1;
    t[i] = c;
  }
  return t;
}
constexpr std::array<uint32_t, 256> kCrcTable = make_crc_table();

uint32_t be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
void put_be32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}

std::string hex(uint32_t v, int digits) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%0*X", digits, v);
  return b;
}
std::string hex_bytes(std::span<const uint8_t> b) {
  std::string s;
  for (uint8_t x : b) {
    char h[4];
    std::snprintf(h, sizeof h, "%02X", x);
    if (!s.empty()) s += ' ';
    s += h;
  }
  return s;
}

Error err(const std::string& what) { return Error{"dsp1760: " + what}; }

// The fields of a packet whose length is known (no checks).
Packet decode(const uint8_t* d) {
  Packet p;
  for (size_t i = 0; i < 3; ++i) p.xyz[i] = std::bit_cast<float>(be32(d + kOffsetX + 4 * i));
  std::memcpy(p.reserved.data(), d + kOffsetReserved, kReservedBytes);
  p.status = d[kOffsetStatus];
  p.sequence = d[kOffsetSequence];
  p.temperature_raw = static_cast<int16_t>((uint16_t{d[kOffsetTemperature]} << 8) | d[kOffsetTemperature + 1]);
  p.crc = be32(d + kOffsetCrc);
  return p;
}

// Why the 36 bytes at `d` (header already matched) are not a packet.
struct Fault {
  enum Kind { kNone, kCrc, kField } kind = kNone;
  std::string why;
};
Fault check(const uint8_t* d) {
  const uint32_t want = crc32_mpeg2(std::span<const uint8_t>(d, kOffsetCrc));
  const uint32_t got = be32(d + kOffsetCrc);
  if (want != got) return {Fault::kCrc, "CRC mismatch: bytes 32-35 say " + hex(got, 8) + ", bytes 0-31 give " + hex(want, 8)};
  if (d[kOffsetSequence] >= kSequenceModulo)
    return {Fault::kField, "sequence (byte 29) is " + std::to_string(d[kOffsetSequence]) + ", not 0-127"};
  return {};
}

template <class E>
Result<E> from_name(const std::string& s, std::initializer_list<E> all, const char* (*name)(E), const char* what) {
  std::string list;
  for (E e : all) {
    if (s == name(e)) return e;
    list += (list.empty() ? "" : ", ") + std::string(name(e));
  }
  return Error{std::string("dsp1760: unknown ") + what + " '" + s + "' (" + list + ")"};
}

}  // namespace

uint32_t crc32_mpeg2(std::span<const uint8_t> data) {
  uint32_t crc = 0xFFFFFFFFu;
  for (uint8_t b : data) crc = (crc << 8) ^ kCrcTable[((crc >> 24) ^ b) & 0xFFu];
  return crc;
}

const char* output_name(Output o) { return o == Output::kRate ? "rate" : "delta"; }
const char* angle_unit_name(AngleUnit u) { return u == AngleUnit::kDegrees ? "deg" : "rad"; }
const char* temperature_unit_name(TemperatureUnit u) {
  switch (u) {
    case TemperatureUnit::kCelsius: return "c";
    case TemperatureUnit::kCentiCelsius: return "c_100";
    case TemperatureUnit::kFahrenheit: return "f";
    case TemperatureUnit::kCentiFahrenheit: return "f_100";
  }
  return "?";
}
Result<Output> output_from_name(const std::string& s) {
  return from_name(s, {Output::kDeltaAngle, Output::kRate}, output_name, "output");
}
Result<AngleUnit> angle_unit_from_name(const std::string& s) {
  return from_name(s, {AngleUnit::kRadians, AngleUnit::kDegrees}, angle_unit_name, "angle unit");
}
Result<TemperatureUnit> temperature_unit_from_name(const std::string& s) {
  return from_name(s,
                   {TemperatureUnit::kCelsius, TemperatureUnit::kCentiCelsius, TemperatureUnit::kFahrenheit,
                    TemperatureUnit::kCentiFahrenheit},
                   temperature_unit_name, "temperature unit");
}

Result<Packet> parse_packet(std::span<const uint8_t> data) {
  if (data.size() < kPacketBytes)
    return err("truncated packet: " + std::to_string(data.size()) + " of " + std::to_string(kPacketBytes) + " bytes");
  if (!std::equal(kHeader.begin(), kHeader.end(), data.begin()))
    return err("header (bytes 0-3) is " + hex_bytes(data.first(4)) + ", not FE 81 FF 55");
  if (auto f = check(data.data()); f.kind != Fault::kNone) return err(f.why);
  return decode(data.data());
}

Bytes encode_packet(const Packet& p) {
  Bytes out(kPacketBytes, 0);
  std::copy(kHeader.begin(), kHeader.end(), out.begin());
  for (size_t i = 0; i < 3; ++i) put_be32(out.data() + kOffsetX + 4 * i, std::bit_cast<uint32_t>(p.xyz[i]));
  std::copy(p.reserved.begin(), p.reserved.end(), out.begin() + kOffsetReserved);
  out[kOffsetStatus] = p.status;
  out[kOffsetSequence] = p.sequence;
  out[kOffsetTemperature] = static_cast<uint8_t>(static_cast<uint16_t>(p.temperature_raw) >> 8);
  out[kOffsetTemperature + 1] = static_cast<uint8_t>(static_cast<uint16_t>(p.temperature_raw) & 0xFF);
  put_be32(out.data() + kOffsetCrc, crc32_mpeg2(std::span<const uint8_t>(out).first(kOffsetCrc)));
  return out;
}

double temperature_c(int16_t raw, TemperatureUnit unit) {
  const double v = raw;
  switch (unit) {
    case TemperatureUnit::kCelsius: return v;
    case TemperatureUnit::kCentiCelsius: return v / 100.0;
    case TemperatureUnit::kFahrenheit: return (v - 32.0) * 5.0 / 9.0;
    case TemperatureUnit::kCentiFahrenheit: return (v / 100.0 - 32.0) * 5.0 / 9.0;
  }
  return v;
}

GyroReading to_gyro_reading(const Packet& p, const Config& c, Time stamp) {
  const double k = c.angle_unit == AngleUnit::kDegrees ? std::numbers::pi / 180.0 : 1.0;
  GyroReading r;
  r.stamp = stamp;
  r.value_G = Vec3(p.xyz[0], p.xyz[1], p.xyz[2]) * k;
  r.is_rate = c.output == Output::kRate;
  r.valid = (p.status & c.axes) == c.axes;
  r.sequence = p.sequence;
  r.temperature_c = temperature_c(p.temperature_raw, c.temperature_unit);
  return r;
}

Packet packet_from(const GyroReading& r, const Config& c) {
  const double k = c.angle_unit == AngleUnit::kDegrees ? 180.0 / std::numbers::pi : 1.0;
  Packet p;
  for (int i = 0; i < 3; ++i) p.xyz[static_cast<size_t>(i)] = static_cast<float>(r.value_G[i] * k);
  p.status = r.valid ? c.axes : 0;
  p.sequence = static_cast<uint8_t>(r.sequence % kSequenceModulo);
  double t = r.temperature_c;
  if (c.temperature_unit == TemperatureUnit::kFahrenheit || c.temperature_unit == TemperatureUnit::kCentiFahrenheit)
    t = t * 9.0 / 5.0 + 32.0;
  if (c.temperature_unit == TemperatureUnit::kCentiCelsius || c.temperature_unit == TemperatureUnit::kCentiFahrenheit)
    t *= 100.0;
  t = std::isfinite(t) ? std::clamp(std::round(t), -32768.0, 32767.0) : 0.0;
  p.temperature_raw = static_cast<int16_t>(t);
  return p;
}

std::vector<std::pair<std::string, std::string>> describe(const Packet& p) {
  std::vector<std::pair<std::string, std::string>> out;
  const char* axes[] = {"X", "Y", "Z"};
  for (size_t i = 0; i < 3; ++i) {
    char b[32];
    std::snprintf(b, sizeof b, "%.9g", static_cast<double>(p.xyz[i]));
    out.emplace_back(axes[i], b);
  }
  if (std::any_of(p.reserved.begin(), p.reserved.end(), [](uint8_t b) { return b != 0; }))
    out.emplace_back("reserved", hex_bytes(p.reserved));
  out.emplace_back("status", hex(p.status, 2));
  out.emplace_back("valid_x", (p.status & kStatusX) ? "true" : "false");
  out.emplace_back("valid_y", (p.status & kStatusY) ? "true" : "false");
  out.emplace_back("valid_z", (p.status & kStatusZ) ? "true" : "false");
  out.emplace_back("sequence", std::to_string(p.sequence));
  out.emplace_back("temperature_raw", std::to_string(p.temperature_raw));
  out.emplace_back("crc", hex(p.crc, 8));
  return out;
}

void StreamParser::push(std::span<const uint8_t> bytes) {
  if (start_ > 0) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
    base_ += start_;
    start_ = 0;
  }
  if (bytes.size() >= kMaxBuffered) {
    const size_t drop = buf_.size() + (bytes.size() - kMaxBuffered);
    stats_.dropped_bytes += drop;
    base_ += drop;
    buf_.assign(bytes.end() - static_cast<std::ptrdiff_t>(kMaxBuffered), bytes.end());
    return;
  }
  if (buf_.size() + bytes.size() > kMaxBuffered) {
    const size_t drop = buf_.size() + bytes.size() - kMaxBuffered;
    stats_.dropped_bytes += drop;
    base_ += drop;
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(drop));
  }
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void StreamParser::reject(std::string why) {
  last_error_ = "dsp1760: byte " + std::to_string(base_ + start_) + ": " + std::move(why);
  start_ += 1;  // only the header's first byte: a real packet may start inside the rejected one
  stats_.skipped_bytes += 1;
}

std::optional<Packet> StreamParser::pop() {
  for (;;) {
    const uint8_t* d = buf_.data();
    const size_t n = buf_.size();
    size_t i = start_;
    // The next header, or a prefix of one at the very end (kept until more bytes come).
    while (i < n) {
      const void* fe = std::memchr(d + i, kHeader[0], n - i);
      if (fe == nullptr) {
        i = n;
        break;
      }
      i = static_cast<size_t>(static_cast<const uint8_t*>(fe) - d);
      if (std::memcmp(d + i, kHeader.data(), std::min<size_t>(kHeader.size(), n - i)) == 0) break;
      ++i;
    }
    stats_.skipped_bytes += i - start_;
    start_ = i;
    if (n - start_ < kPacketBytes) return std::nullopt;
    const uint8_t* at = d + start_;
    if (auto f = check(at); f.kind != Fault::kNone) {
      ++(f.kind == Fault::kCrc ? stats_.bad_crc : stats_.bad_field);
      reject(std::move(f.why));
      continue;
    }
    Packet p = decode(at);
    start_ += kPacketBytes;
    ++stats_.accepted;
    last_missing_ = 0;
    if (last_sequence_) {
      const unsigned expected = (*last_sequence_ + 1u) % kSequenceModulo;
      if (p.sequence != expected) {
        last_missing_ = (p.sequence + kSequenceModulo - expected) % kSequenceModulo;
        ++stats_.sequence_gaps;
        stats_.missing_packets += last_missing_;
      }
    }
    last_sequence_ = p.sequence;
    return p;
  }
}

}  // namespace orthosonar::hal::drivers::dsp1760
