// KVH DSP-1760: the wire format, the CRC variant, stream framing and counts, conversion to
// GyroReading, devices.yaml, the inspect decoder and the live path (serial and emulator).
#include "hal/drivers/dsp1760.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <numbers>
#include <random>
#include <stdlib.h>
#include <thread>
#include <unistd.h>

#include "hal/drivers/driver_device.hpp"
#include "hal/drivers/emulator.hpp"
#include "hal/drivers/live_source.hpp"
#include "hal/drivers/protocol_decoder.hpp"
#include "hal/drivers/test_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;
using dsp1760::Packet;

namespace {

// Generic CRC-32, bit by bit (the parameters of the CRC catalogue): the slow, obvious
// reference for the table-driven crc32_mpeg2() and the rival variants of the proof.
struct CrcParams {
  const char* name;
  uint32_t poly, init;
  bool reflect;
  uint32_t xorout;
};
uint32_t reflect32(uint32_t v) {
  uint32_t r = 0;
  for (int i = 0; i < 32; ++i) r |= ((v >> i) & 1u) << (31 - i);
  return r;
}
uint32_t crc_bitwise(const CrcParams& p, std::span<const uint8_t> data) {
  uint32_t crc = p.init;
  for (uint8_t byte : data) {
    uint8_t b = byte;
    if (p.reflect) {
      uint8_t r = 0;
      for (int i = 0; i < 8; ++i) r = static_cast<uint8_t>(r | (((b >> i) & 1) << (7 - i)));
      b = r;
    }
    crc ^= static_cast<uint32_t>(b) << 24;
    for (int k = 0; k < 8; ++k) crc = (crc & 0x80000000u) ? (crc << 1) ^ p.poly : crc << 1;
  }
  if (p.reflect) crc = reflect32(crc);
  return crc ^ p.xorout;
}
constexpr CrcParams kMpeg2{"CRC-32/MPEG-2", 0x04C11DB7, 0xFFFFFFFF, false, 0};
constexpr CrcParams kRivals[] = {
    {"CRC-32/ISO-HDLC (zlib, Ethernet)", 0x04C11DB7, 0xFFFFFFFF, true, 0xFFFFFFFF},
    {"CRC-32/BZIP2", 0x04C11DB7, 0xFFFFFFFF, false, 0xFFFFFFFF},
    {"CRC-32/CKSUM (POSIX)", 0x04C11DB7, 0, false, 0xFFFFFFFF},
    {"CRC-32/JAMCRC", 0x04C11DB7, 0xFFFFFFFF, true, 0},
    {"CRC-32C (Castagnoli)", 0x1EDC6F41, 0xFFFFFFFF, true, 0xFFFFFFFF},
};

uint32_t be32(const uint8_t* p) { return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | p[3]; }
uint32_t le32(const uint8_t* p) { return uint32_t{p[3]} << 24 | uint32_t{p[2]} << 16 | uint32_t{p[1]} << 8 | p[0]; }

// A packet of a KVH 1750 IMU (the same "Format A" message as the DSP-1760's, accelerations
// where the gyro has reserved bytes), published as test data by a public KVH 1750 decoder.
const Bytes kKvh1750 = {0xFE, 0x81, 0xFF, 0x55, 0x37, 0xA9, 0x6A, 0x6E, 0x38, 0x58, 0x6C, 0x1F,
                        0xB7, 0x5B, 0xF8, 0x62, 0xBF, 0x80, 0x3E, 0x78, 0xBB, 0x65, 0x0D, 0x28,
                        0x3B, 0x0A, 0x37, 0xAC, 0x77, 0x3D, 0x00, 0x28, 0x4B, 0xFA, 0x34, 0xD8};

Packet make_packet(float x, float y, float z, uint8_t seq, uint8_t status = dsp1760::kStatusXyz, int16_t temp = 25) {
  Packet p;
  p.xyz = {x, y, z};
  p.status = status;
  p.sequence = seq;
  p.temperature_raw = temp;
  return p;
}

struct Parsed {
  std::vector<Packet> packets;
  dsp1760::StreamStats stats;
  size_t buffered = 0;
};
Parsed parse_stream(const Bytes& wire, size_t step) {
  dsp1760::StreamParser parser;
  Parsed out;
  for (size_t at = 0; at < wire.size(); at += step) {
    parser.push(std::span<const uint8_t>(wire).subspan(at, std::min(step, wire.size() - at)));
    while (auto p = parser.pop()) out.packets.push_back(*p);
  }
  out.stats = parser.stats();
  out.buffered = parser.buffered();
  return out;
}

void append(Bytes& wire, const Bytes& b) { wire.insert(wire.end(), b.begin(), b.end()); }

}  // namespace

TEST_CASE("dsp1760: CRC-32/MPEG-2 gives the catalogue check value and equals the bitwise reference", "[hal]") {
  const std::string check = "123456789";
  CHECK(dsp1760::crc32_mpeg2(as_bytes(check)) == 0x0376E6E7u);
  std::mt19937 rng(7);
  for (size_t n : {0u, 1u, 31u, 32u, 36u, 1000u}) {
    Bytes b(n);
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    CHECK(dsp1760::crc32_mpeg2(b) == crc_bitwise(kMpeg2, b));
  }
}

TEST_CASE("dsp1760: the CRC is CRC-32/MPEG-2 over bytes 0-31, big-endian: no other common CRC-32 verifies a real KVH packet", "[hal]") {
  const auto body = std::span<const uint8_t>(kKvh1750).first(32);
  const uint32_t field_be = be32(kKvh1750.data() + 32), field_le = le32(kKvh1750.data() + 32);
  CHECK(crc_bitwise(kMpeg2, body) == field_be);
  CHECK(dsp1760::crc32_mpeg2(body) == 0x4BFA34D8u);
  CHECK(crc_bitwise(kMpeg2, body) != field_le);
  // Without the header the CRC does not verify either: it covers the header.
  CHECK(crc_bitwise(kMpeg2, body.subspan(4)) != field_be);
  for (const auto& rival : kRivals) {
    INFO(rival.name);
    CHECK(crc_bitwise(rival, body) != field_be);
    CHECK(crc_bitwise(rival, body) != field_le);
  }
  // No reflection and no final xor: the CRC of the whole packet is zero.
  CHECK(dsp1760::crc32_mpeg2(kKvh1750) == 0u);
  // The decoder accepts it (status 0x77: the IMU's accelerometer bits 4-6 besides X Y Z).
  auto p = dsp1760::parse_packet(kKvh1750);
  REQUIRE(p.ok());
  CHECK(p->status == 0x77);
  CHECK(p->sequence == 61);
  CHECK(p->temperature_raw == 40);
  CHECK(p->xyz[0] == Approx(2.0195930e-05).epsilon(1e-6));
  CHECK(dsp1760::to_gyro_reading(*p, {}, Time()).valid);
}

TEST_CASE("dsp1760: a packet laid out by hand from the published layout decodes, and encodes to the same bytes", "[hal]") {
  // X = 1.0 (3F800000), Y = -0.5 (BF000000), Z = 2^-13 (39000000), status 0x07, seq 100,
  // temperature -1234 (FB2E), CRC computed by the bitwise reference.
  Bytes b = {0xFE, 0x81, 0xFF, 0x55, 0x3F, 0x80, 0x00, 0x00, 0xBF, 0x00, 0x00, 0x00, 0x39, 0x00, 0x00, 0x00};
  b.resize(28, 0x00);
  for (uint8_t x : std::array<uint8_t, 4>{0x07, 100, 0xFB, 0x2E}) b.push_back(x);
  const uint32_t crc = crc_bitwise(kMpeg2, b);
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(crc >> (24 - 8 * i)));
  REQUIRE(b.size() == dsp1760::kPacketBytes);
  auto p = dsp1760::parse_packet(b);
  REQUIRE(p.ok());
  CHECK(p->xyz == std::array<float, 3>{1.0f, -0.5f, 0x1p-13f});
  CHECK(p->status == 0x07);
  CHECK(p->sequence == 100);
  CHECK(p->temperature_raw == -1234);
  CHECK(p->crc == crc);
  CHECK(dsp1760::encode_packet(*p) == b);
  const auto fields = dsp1760::describe(*p);
  REQUIRE(fields.size() == 10);
  CHECK(fields[0] == std::pair<std::string, std::string>{"X", "1"});
  CHECK(fields[3] == std::pair<std::string, std::string>{"status", "0x07"});
  char crc_text[16];
  std::snprintf(crc_text, sizeof crc_text, "0x%08X", crc);
  CHECK(fields.back() == std::pair<std::string, std::string>{"crc", crc_text});
}

TEST_CASE("dsp1760: the capture written by Python's struct and a hand CRC decodes to its documented packets", "[hal]") {
  const auto capture = testing::read_file(testing::testdata("dsp1760/python_struct.bin"));
  REQUIRE(capture.size() == 208);
  for (size_t step : {size_t{1}, size_t{7}, size_t{36}, capture.size()}) {
    INFO("read size " << step);
    const Parsed r = parse_stream(capture, step);
    REQUIRE(r.packets.size() == 4);
    CHECK(r.packets[0].xyz == std::array<float, 3>{0x1p-13f, -0x1p-12f, 0x1p-14f});
    CHECK(r.packets[0].sequence == 126);
    CHECK(r.packets[0].temperature_raw == 2500);
    CHECK(r.packets[1].xyz == std::array<float, 3>{0.0f, 1.5f, -0.25f});
    CHECK(r.packets[1].status == 0x03);
    CHECK(r.packets[2].sequence == 0);
    CHECK(r.packets[2].temperature_raw == -1050);
    CHECK(r.packets[3].sequence == 3);
    CHECK(r.packets[3].xyz == std::array<float, 3>{3.0e-4f, -7.0e-5f, 1.0e-6f});
    CHECK(r.stats.accepted == 4);
    CHECK(r.stats.bad_crc == 1);
    CHECK(r.stats.bad_field == 0);
    CHECK(r.stats.sequence_gaps == 1);  // 127 -> 0 is no gap; 0 -> 3 is one, of 2 packets
    CHECK(r.stats.missing_packets == 2);
    CHECK(r.stats.skipped_bytes == 8 + 36);
    CHECK(r.buffered == 20);  // the truncated packet at the end waits for its last 16 bytes
  }
  dsp1760::Config c;
  c.temperature_unit = dsp1760::TemperatureUnit::kCentiCelsius;
  const Parsed r = parse_stream(capture, capture.size());
  CHECK_FALSE(dsp1760::to_gyro_reading(r.packets[1], c, Time()).valid);  // Z invalid
  CHECK(dsp1760::to_gyro_reading(r.packets[1], c, Time()).temperature_c == Approx(25.12));
  CHECK(dsp1760::to_gyro_reading(r.packets[2], c, Time()).temperature_c == Approx(-10.5));
}

TEST_CASE("dsp1760: resynchronises on the header after garbage, false header prefixes and split reads", "[hal]") {
  std::mt19937 rng(11);
  Bytes wire;
  size_t garbage = 0;
  for (uint8_t seq = 0; seq < 40; ++seq) {
    Bytes junk(rng() % 50);
    for (auto& x : junk) x = static_cast<uint8_t>(rng() % 3 == 0 ? 0xFE : rng());
    if (seq % 5 == 0) junk.insert(junk.end(), {0xFE, 0x81, 0xFF});  // a header cut short
    if (seq % 7 == 0) junk.insert(junk.end(), {0xFE, 0x81, 0xFF, 0x55, 0x00});  // a header with no packet
    garbage += junk.size();
    append(wire, junk);
    append(wire, dsp1760::encode_packet(make_packet(0.001f * seq, 0.0f, -0.001f, seq)));
  }
  for (size_t step : {size_t{1}, size_t{5}, size_t{64}, wire.size()}) {
    INFO("read size " << step);
    const Parsed r = parse_stream(wire, step);
    REQUIRE(r.packets.size() == 40);
    for (uint8_t i = 0; i < 40; ++i) CHECK(r.packets[i].sequence == i);
    CHECK(r.stats.sequence_gaps == 0);
    CHECK(r.stats.skipped_bytes == garbage);
    CHECK(r.buffered == 0);
    // A header with no packet behind it fails the CRC (the next 32 bytes are not its own).
    CHECK(r.stats.bad_crc == 6);
  }
}

TEST_CASE("dsp1760: a bad CRC is counted and a packet starting inside the rejected bytes is still found", "[hal]") {
  const Bytes good = dsp1760::encode_packet(make_packet(0.5f, 0.25f, 0.125f, 9));
  Bytes wire(good.begin(), good.begin() + 10);  // a packet cut after 10 bytes ...
  append(wire, good);                           // ... then a whole one
  Bytes corrupt = dsp1760::encode_packet(make_packet(0.5f, 0.25f, 0.125f, 10));
  corrupt[17] ^= 0x01;  // one bit of a reserved byte
  append(wire, corrupt);
  append(wire, dsp1760::encode_packet(make_packet(0.5f, 0.25f, 0.125f, 11)));
  dsp1760::StreamParser parser;
  parser.push(wire);
  std::vector<Packet> got;
  while (auto p = parser.pop()) got.push_back(*p);
  REQUIRE(got.size() == 2);
  CHECK(got[0].sequence == 9);
  CHECK(got[1].sequence == 11);
  CHECK(parser.stats().bad_crc == 2);
  CHECK(parser.stats().skipped_bytes == 10 + 36);
  CHECK(parser.stats().sequence_gaps == 1);  // the corrupted packet is a lost one
  CHECK(parser.stats().missing_packets == 1);
  CHECK(parser.malformed() == 2);
  auto single = dsp1760::parse_packet(corrupt);
  REQUIRE_FALSE(single.ok());
  CHECK(single.error().message.find("CRC mismatch: bytes 32-35") != std::string::npos);
}

TEST_CASE("dsp1760: sequence gaps are counted, with the counter wrapping 127 -> 0", "[hal]") {
  auto gaps_of = [](std::vector<uint8_t> seqs) {
    Bytes wire;
    for (uint8_t s : seqs) append(wire, dsp1760::encode_packet(make_packet(0, 0, 0, s)));
    return parse_stream(wire, wire.size()).stats;
  };
  auto s = gaps_of({124, 125, 126, 127, 0, 1, 2});
  CHECK(s.accepted == 7);
  CHECK(s.sequence_gaps == 0);
  s = gaps_of({126, 127, 1});  // 0 lost at the wrap
  CHECK(s.sequence_gaps == 1);
  CHECK(s.missing_packets == 1);
  s = gaps_of({120, 5, 6, 10});  // 121..127 and 0..4 lost, then 7..9
  CHECK(s.sequence_gaps == 2);
  CHECK(s.missing_packets == 12 + 3);
  s = gaps_of({50, 50});  // a repeat aliases to a gap of 127 (documented: counts are mod 128)
  CHECK(s.sequence_gaps == 1);
  CHECK(s.missing_packets == 127);
  // A counter beyond 0-127 with a good CRC is a bad field, never taken as a packet.
  Bytes wire = dsp1760::encode_packet(make_packet(0, 0, 0, 200));
  append(wire, dsp1760::encode_packet(make_packet(0, 0, 0, 7)));
  const Parsed r = parse_stream(wire, wire.size());
  REQUIRE(r.packets.size() == 1);
  CHECK(r.stats.bad_field == 1);
  auto e = dsp1760::parse_packet(dsp1760::encode_packet(make_packet(0, 0, 0, 200)));
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().message == "dsp1760: sequence (byte 29) is 200, not 0-127");
}

TEST_CASE("dsp1760: a truncated packet at the end is kept, not decoded, and completes when the rest comes", "[hal]") {
  const Bytes b = dsp1760::encode_packet(make_packet(1, 2, 3, 4));
  for (size_t cut = 0; cut < b.size(); ++cut) {
    auto one = dsp1760::parse_packet(std::span<const uint8_t>(b).first(cut));
    REQUIRE_FALSE(one.ok());
    CHECK(one.error().message == "dsp1760: truncated packet: " + std::to_string(cut) + " of 36 bytes");
    dsp1760::StreamParser parser;
    parser.push(std::span<const uint8_t>(b).first(cut));
    CHECK_FALSE(parser.pop().has_value());
    CHECK(parser.buffered() == cut);
    parser.push(std::span<const uint8_t>(b).subspan(cut));
    CHECK(parser.pop().has_value());
  }
  Bytes bad_header = b;
  bad_header[3] = 0x56;  // the IMUs' Format B
  auto e = dsp1760::parse_packet(bad_header);
  REQUIRE_FALSE(e.ok());
  CHECK(e.error().message == "dsp1760: header (bytes 0-3) is FE 81 FF 56, not FE 81 FF 55");
}

TEST_CASE("dsp1760: delta angles or rates, radians or degrees, temperature units and axes, per configuration", "[hal]") {
  const Packet p = make_packet(0.5f, -1.0f, 2.0f, 17, dsp1760::kStatusX | dsp1760::kStatusY, 2150);
  dsp1760::Config c;  // delta angles, radians, whole degrees C, all three axes
  GyroReading r = dsp1760::to_gyro_reading(p, c, Time::from_ms(5));
  CHECK_FALSE(r.is_rate);
  CHECK(r.value_G == Vec3(0.5, -1.0, 2.0));
  CHECK_FALSE(r.valid);
  CHECK(r.sequence == 17);
  CHECK(r.temperature_c == 2150.0);
  CHECK(r.stamp == Time::from_ms(5));
  c.output = dsp1760::Output::kRate;
  c.angle_unit = dsp1760::AngleUnit::kDegrees;
  c.axes = dsp1760::kStatusX | dsp1760::kStatusY;  // a 2-axis unit
  c.temperature_unit = dsp1760::TemperatureUnit::kCentiCelsius;
  r = dsp1760::to_gyro_reading(p, c, Time());
  CHECK(r.is_rate);
  CHECK(r.value_G.x() == Approx(0.5 * std::numbers::pi / 180.0));
  CHECK(r.value_G.z() == Approx(2.0 * std::numbers::pi / 180.0));
  CHECK(r.valid);
  CHECK(r.temperature_c == Approx(21.5));
  CHECK(dsp1760::temperature_c(212, dsp1760::TemperatureUnit::kFahrenheit) == Approx(100.0));
  CHECK(dsp1760::temperature_c(-4000, dsp1760::TemperatureUnit::kCentiFahrenheit) == Approx(-40.0));
  // The emulator's direction: a reading goes out in the configured units and comes back.
  for (auto unit : {dsp1760::TemperatureUnit::kCelsius, dsp1760::TemperatureUnit::kCentiCelsius,
                    dsp1760::TemperatureUnit::kFahrenheit, dsp1760::TemperatureUnit::kCentiFahrenheit}) {
    GyroReading g;
    g.value_G = Vec3(1e-4, -2e-5, 3e-6);
    g.is_rate = true;
    g.sequence = 130;
    g.temperature_c = 31.25;
    c.temperature_unit = unit;
    const auto back = dsp1760::to_gyro_reading(*dsp1760::parse_packet(dsp1760::encode_packet(dsp1760::packet_from(g, c))), c, Time());
    CHECK((back.value_G - g.value_G).norm() < 1e-10);
    CHECK(back.sequence == 2);
    CHECK(back.valid);
    CHECK(std::abs(back.temperature_c - 31.25) <= (unit == dsp1760::TemperatureUnit::kCelsius ? 0.5 : 0.3));
  }
  CHECK(dsp1760::output_from_name("rate").ok());
  auto bad = dsp1760::output_from_name("angle");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message == "dsp1760: unknown output 'angle' (delta, rate)");
}

TEST_CASE("dsp1760: inspect --protocol dsp1760 gives offsets, fields, counts and the gap", "[hal]") {
  const auto capture = testing::read_file(testing::testdata("dsp1760/python_struct.bin"));
  REQUIRE(protocol_from_name("dsp1760").ok());
  CHECK(protocol_name(Protocol::kDsp1760) == std::string("dsp1760"));
  auto d = make_decoder(Protocol::kDsp1760);
  std::vector<DecodedMessage> msgs;
  for (size_t at = 0; at < capture.size(); at += 13) {
    d->push(std::span<const uint8_t>(capture).subspan(at, std::min<size_t>(13, capture.size() - at)));
    while (auto m = d->pop()) msgs.push_back(*m);
  }
  d->finish();
  while (auto m = d->pop()) msgs.push_back(*m);
  REQUIRE(msgs.size() == 4);
  CHECK(msgs[0].offset == 8);
  CHECK(msgs[1].offset == 44);
  CHECK(msgs[2].offset == 80);
  CHECK(msgs[3].offset == 152);
  CHECK(msgs[3].fields.back() == std::pair<std::string, std::string>{"missing_before", "2"});
  CHECK(msgs[1].fields[6] == std::pair<std::string, std::string>{"valid_z", "false"});
  const DecodeCounts c = d->counts();
  CHECK(c.good == 4);
  CHECK(c.bad == 1);
  CHECK(c.skipped_bytes == 44);
  CHECK(c.trailing_bytes == 20);
  REQUIRE(c.sequence_gaps.has_value());
  CHECK(*c.sequence_gaps == 1);
  CHECK(c.missing_packets == 2);
  CHECK(c.last_error.rfind("dsp1760: byte 116: CRC mismatch: bytes 32-35 say 0x", 0) == 0);
}

TEST_CASE("dsp1760: devices.yaml kind dsp1760 with its options, defaults and errors", "[hal]") {
  auto c = parse_live_config(
      "devices:\n"
      "  - {name: fog, kind: dsp1760, serial: /dev/ttyUSB1}\n"
      "  - {name: fog2, kind: dsp1760, address: 10.0.0.2, port: 4001, output: rate, angle_units: deg,"
      " temperature_units: f_100}\n");
  REQUIRE(c.ok());
  const auto& a = c->devices[0];
  CHECK(a.kind == DeviceKind::kDsp1760);
  CHECK(a.baud == 921600);
  CHECK(a.gyro == dsp1760::Config{});
  const auto& b = c->devices[1];
  CHECK(b.gyro.output == dsp1760::Output::kRate);
  CHECK(b.gyro.angle_unit == dsp1760::AngleUnit::kDegrees);
  CHECK(b.gyro.temperature_unit == dsp1760::TemperatureUnit::kCentiFahrenheit);
  auto again = parse_live_config(to_yaml(*c));
  REQUIRE(again.ok());
  CHECK(again->devices[1].gyro == b.gyro);
  CHECK(again->devices[0].serial_path == "/dev/ttyUSB1");
  auto mount = parse_live_config("devices: [{name: fog, kind: dsp1760, port: 1, mount_rpy_deg: [0, 0, 0]}]");
  REQUIRE_FALSE(mount.ok());
  CHECK(mount.error().message.find("unknown key 'mount_rpy_deg' in device 'fog' (dsp1760)") != std::string::npos);
  auto out = parse_live_config("devices: [{name: fog, kind: dsp1760, port: 1, output: angles}]");
  REQUIRE_FALSE(out.ok());
  CHECK(out.error().message == "devices.yaml: device 'fog': output: dsp1760: unknown output 'angles' (delta, rate)");
}

TEST_CASE("dsp1760 over a serial port (pseudo-terminal) at 921600 baud, rates configured", "[hal]") {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  REQUIRE(master >= 0);
  Fd m(master);
  REQUIRE(::grantpt(master) == 0);
  REQUIRE(::unlockpt(master) == 0);
  DeviceConfig c;
  c.name = "fog";
  c.kind = DeviceKind::kDsp1760;
  c.serial_path = ::ptsname(master);
  c.baud = 921600;
  c.gyro.output = dsp1760::Output::kRate;
  DriverDevice dev(c, ReconnectPolicy{});
  REQUIRE(dev.connect().ok());
  Bytes wire = {'n', 'o', 'i', 's', 'e'};
  for (uint8_t s : std::array<uint8_t, 3>{126, 127, 1}) append(wire, dsp1760::encode_packet(make_packet(0.25f, 0, 0, s)));
  REQUIRE(::write(master, wire.data(), wire.size()) == static_cast<ssize_t>(wire.size()));
  std::vector<Payload> got;
  for (int i = 0; i < 300 && got.size() < 3; ++i) {
    dev.wait(std::chrono::milliseconds(10));
    auto r = dev.read();
    REQUIRE(r.ok());
    for (auto& p : *r) got.push_back(std::move(p));
  }
  REQUIRE(got.size() == 3);
  const auto& g = std::get<GyroReading>(got[2]);
  CHECK(g.is_rate);
  CHECK(g.value_G.x() == 0.25);
  CHECK(g.sequence == 1);
  CHECK(channel_of(got[2]) == Channel::kGyro);
  CHECK(dev.health().messages_ok == 3);
  CHECK(dev.health().sequence_gaps == 1);
}

TEST_CASE("dsp1760: the emulator serves a mission's gyro readings and the live source delivers them on /gyro", "[hal]") {
  std::vector<Payload> payloads;
  for (int i = 0; i < 100; ++i) {  // 0.4 s at 250 Hz
    GyroReading g;
    g.stamp = Time::from_ms(4 * i);
    g.value_G = Vec3(1e-5 * i, -2e-6, 7e-7 * (i % 5));
    g.valid = i != 30;
    g.sequence = static_cast<uint8_t>((i + 100) % 128);
    g.temperature_c = 24.0 + 0.01 * i;
    payloads.emplace_back(g);
  }
  const auto mission = hal::make_events(payloads);
  EmulatorOptions eo;
  eo.rate = 2.0;
  MissionEmulator emu(mission, eo);
  REQUIRE(emu.start().ok());
  LiveConfig lc = emu.live_config();
  REQUIRE(lc.devices.size() == 1);
  CHECK(lc.devices[0].kind == DeviceKind::kDsp1760);
  CHECK(lc.devices[0].name == "gyro");
  auto yaml = parse_live_config(to_yaml(lc));  // what `orthosonar emulate --devices-out` writes
  REQUIRE(yaml.ok());
  LiveSource live(*yaml);
  REQUIRE(live.start().ok());
  std::thread stopper([&] {
    emu.wait_finished(std::chrono::milliseconds(8000));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    live.stop();
  });
  std::vector<GyroReading> got;
  for (auto p = live.next(); !p.end_of_stream; p = live.next())
    if (p.event) {
      CHECK(p.event->channel == Channel::kGyro);
      got.push_back(std::get<GyroReading>(p.event->payload));
    }
  stopper.join();
  const LiveReport report = live.report();
  INFO(report_json(report));
  REQUIRE(got.size() == 100);
  for (size_t i = 0; i < got.size(); ++i) {
    const auto& want = std::get<GyroReading>(payloads[i]);
    CHECK(got[i].value_G == want.value_G.cast<float>().cast<double>());
    CHECK(got[i].valid == want.valid);
    CHECK(got[i].sequence == want.sequence);
    CHECK_FALSE(got[i].is_rate);
    CHECK(got[i].temperature_c == Approx(want.temperature_c).margin(0.006));
  }
  CHECK(report.devices[0].health.sequence_gaps == 0);
  CHECK(report.devices[0].health.messages_malformed == 0);
}
