// VN-100 binary output: the real log testdata/vn100/F00294 (IMU + Attitude groups between the
// logger's ASCII lines) against the logger author's own decoding, framing and resync, the
// orientation sources of to_imu_reading(), and encode/decode round trips of random group and
// field selections (rapidcheck; RC_PARAMS="seed=..." replays).
#include <rapidcheck/catch.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "hal/drivers/test_support.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace {

// The real log's packet header and length: groups 0x14 (IMU 0x04 + Attitude 0x10), IMU fields
// 0x003E, Attitude fields 0x003A; 29 float32 fields (testdata/vn100/README.md).
const Bytes kRealHeader = {0xFA, 0x14, 0x3E, 0x00, 0x3A, 0x00};
constexpr size_t kRealPacket = 1 + 1 + 2 * 2 + 29 * 4 + 2;  // 124

struct Vn100Decoded {
  std::vector<vn100::Message> messages;
  vn100::StreamStats stats;
  size_t buffered = 0;
};

// Pushes `bytes` in chunks of the given sizes (cycled), popping after each push.
Vn100Decoded decode_stream(const Bytes& bytes, const std::vector<size_t>& chunks = {1u << 20}) {
  vn100::StreamParser p;
  Vn100Decoded d;
  size_t at = 0, k = 0;
  while (at < bytes.size()) {
    const size_t n = std::min(chunks[k++ % chunks.size()], bytes.size() - at);
    p.push(std::span<const uint8_t>(bytes).subspan(at, n));
    at += n;
    while (auto m = p.pop()) d.messages.push_back(std::move(*m));
  }
  d.stats = p.stats();
  d.buffered = p.buffered();
  return d;
}

Bytes with_crc(Bytes b) {
  const uint16_t crc = vn100::crc16_xmodem(std::span<const uint8_t>(b).subspan(1));
  b.push_back(static_cast<uint8_t>(crc >> 8));
  b.push_back(static_cast<uint8_t>(crc & 0xFF));
  return b;
}

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

// The 29 floats of a real-log packet in wire order, which is also the CSV's column order.
std::vector<float> real_fields(const vn100::Message& m) {
  std::vector<float> v;
  auto add = [&](const auto& a) { v.insert(v.end(), a.begin(), a.end()); };
  add(*m.imu.uncomp_mag);
  add(*m.imu.uncomp_accel);
  add(*m.imu.uncomp_gyro);
  v.push_back(*m.imu.temp_c);
  v.push_back(*m.imu.pres_kpa);
  add(*m.attitude.ypr_deg);
  add(*m.attitude.dcm);
  add(*m.attitude.mag_ned);
  add(*m.attitude.accel_ned);
  return v;
}

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto b = cell.find_first_not_of(" \r");
    if (b == std::string::npos) continue;  // the trailing comma
    out.push_back(cell.substr(b, cell.find_last_not_of(" \r") - b + 1));
  }
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Quat q_ned_frd_of(const std::array<float, 4>& xyzw) { return Quat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized(); }

}  // namespace

TEST_CASE("CRC16-XMODEM matches the standard check value", "[hal]") {
  const std::string s = "123456789";
  CHECK(vn100::crc16_xmodem(as_bytes(s)) == 0x31C3);
}

TEST_CASE("VN-100 packets round-trip and convert NED/FRD to REP-103", "[hal]") {
  ImuReading r;
  r.stamp = Time::from_ms(1234);
  r.q_W_V = Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(0.1, Vec3::UnitY()) *
                 Eigen::AngleAxisd(-0.05, Vec3::UnitX()));
  r.angular_velocity_V = Vec3(0.01, -0.02, 0.3);
  r.linear_acceleration_V = Vec3(0.1, 0.2, 9.81);
  const vn100::Message m = vn100::message_from(r, Quat::Identity());
  const Bytes wire = vn100::encode_packet(m);
  CHECK(wire.size() == 1 + 1 + 2 + 8 + 16 + 12 + 12 + 2);
  CHECK(wire[0] == 0xFA);
  CHECK(wire[1] == vn100::kGroupCommon);
  CHECK(vn100::crc16_xmodem(std::span<const uint8_t>(wire).subspan(1)) == 0);
  auto back = vn100::parse_packet(wire);
  REQUIRE(back.ok());
  CHECK(*back == m);
  // At rest, level: accelerometer reads -g on the NED/FRD z axis.
  CHECK((*back->accel)[2] == Approx(-9.81f));
  auto imu = vn100::to_imu_reading(*back, Quat::Identity(), r.stamp);
  REQUIRE(imu.ok());
  CHECK(imu->q_W_V.angularDistance(r.q_W_V) < 1e-6);
  CHECK((imu->angular_velocity_V - r.angular_velocity_V).norm() < 1e-6);
  CHECK((imu->linear_acceleration_V - r.linear_acceleration_V).norm() < 1e-5);
  // Yaw 90 degrees in NED (facing east) is yaw 0 in ENU.
  vn100::Message ypr;
  ypr.ypr_deg = std::array<float, 3>{90.0f, 0.0f, 0.0f};
  auto east = vn100::to_imu_reading(*vn100::parse_packet(vn100::encode_packet(ypr)), Quat::Identity(), Time());
  REQUIRE(east.ok());
  CHECK(yaw_of(east->q_W_V) == Approx(0.0).margin(1e-6));
  ypr.ypr_deg = std::array<float, 3>{0.0f, 0.0f, 0.0f};  // facing north = +90 degrees in ENU
  auto north = vn100::to_imu_reading(*vn100::parse_packet(vn100::encode_packet(ypr)), Quat::Identity(), Time());
  CHECK(yaw_of(north->q_W_V) == Approx(M_PI / 2));
}

TEST_CASE("VN-100 stream resyncs after garbage and a bad CRC", "[hal]") {
  vn100::Message m;
  m.quat_xyzw = std::array<float, 4>{0, 0, 0, 1};
  Bytes good = vn100::encode_packet(m);
  Bytes bad = good;
  bad[6] ^= 0x40;
  Bytes stream = {0x01, 0xFA, 0x07, 0x33};
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), good.begin(), good.end());
  stream.insert(stream.end(), good.begin(), good.begin() + 5);
  vn100::StreamParser p;
  int n = 0;
  for (uint8_t b : stream) {
    p.push(std::span<const uint8_t>(&b, 1));
    while (p.pop()) ++n;
  }
  CHECK(n == 1);
  CHECK(p.malformed() >= 2);
  CHECK(p.buffered() == 5);  // the start of the last packet, waiting for the rest
}

TEST_CASE("VN-100 packet length comes from the group and field masks", "[hal]") {
  using S = vn100::PacketLength::Status;
  const auto len = vn100::packet_length(kRealHeader);
  REQUIRE(len.status == S::kKnown);
  CHECK(len.bytes == kRealPacket);
  CHECK(len.bytes == 124);
  // Too few bytes to read every mask: wait.
  CHECK(vn100::packet_length(std::span<const uint8_t>(kRealHeader).first(5)).status == S::kNeedMoreBytes);
  CHECK(vn100::packet_length(std::span<const uint8_t>(kRealHeader).first(1)).status == S::kNeedMoreBytes);
  // Sizes from the ICD tables.
  CHECK(vn100::field_size(vn100::kGroupImu, 1) == 12u);       // UncompMag
  CHECK(vn100::field_size(vn100::kGroupImu, 6) == 16u);       // DeltaTheta: dtime + 3 floats
  CHECK(vn100::field_size(vn100::kGroupAttitude, 3) == 36u);  // DCM
  CHECK(vn100::field_size(vn100::kGroupAttitude, 8) == 12u);  // YprU
  CHECK(vn100::field_size(vn100::kGroupAttitude, 12) == 12u); // Heave
  CHECK(vn100::field_size(vn100::kGroupCommon, 6) == 24u);    // Position: 3 doubles
  CHECK(vn100::field_size(vn100::kGroupCommon, 11) == 28u);   // DeltaTheta + DeltaVel
  CHECK(vn100::field_size(vn100::kGroupTime, 6) == 8u);       // TimeUtc
  CHECK(vn100::field_size(vn100::kGroupTime, 9) == 1u);       // TimeStatus
  CHECK_FALSE(vn100::field_size(vn100::kGroupAttitude, 9));   // undocumented
  CHECK_FALSE(vn100::field_size(vn100::kGroupTime, 10));      // reserved
  CHECK_FALSE(vn100::field_size(vn100::kGroupCommon, 15));    // extension bit
  CHECK_FALSE(vn100::field_size(0x08, 0));                    // GNSS group: not decoded
}

TEST_CASE("VN-100 real log: all 99 packets decode, the ASCII between them is skipped and counted", "[hal]") {
  const Bytes raw = testing::read_file(testing::testdata("vn100/F00294"));
  REQUIRE(raw.size() == 15043);

  // Independently of the parser: the packets are where the header bytes occur, each 124 bytes;
  // everything else must be the logger's text lines ($GP... sentences, "M,<ms>", "B,", blank).
  std::vector<size_t> at;
  for (auto it = raw.begin(); (it = std::search(it, raw.end(), kRealHeader.begin(), kRealHeader.end())) != raw.end(); ++it)
    at.push_back(static_cast<size_t>(it - raw.begin()));
  REQUIRE(at.size() == 99);
  std::string outside;
  size_t prev = 0;
  for (size_t p : at) {
    REQUIRE(p >= prev);
    outside.append(raw.begin() + static_cast<std::ptrdiff_t>(prev), raw.begin() + static_cast<std::ptrdiff_t>(p));
    prev = p + kRealPacket;
  }
  outside.append(raw.begin() + static_cast<std::ptrdiff_t>(prev), raw.end());
  size_t text_lines = 0;
  std::stringstream lines(outside);
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    INFO(line);
    CHECK((line.empty() || line.rfind("$GP", 0) == 0 || line.rfind("M,", 0) == 0 || line == "B,"));
    CHECK(std::all_of(line.begin(), line.end(), [](char c) { return c >= 32 && c < 127; }));
    text_lines += !line.empty();
  }
  CHECK(outside.size() == 2767);
  CHECK(text_lines > 99);

  for (const auto& chunks : {std::vector<size_t>{1u << 20}, std::vector<size_t>{1}, std::vector<size_t>{7, 1, 123, 2, 64}}) {
    const Vn100Decoded d = decode_stream(raw, chunks);
    CHECK(d.messages.size() == 99);
    CHECK(d.stats.accepted == 99);
    CHECK(d.stats.bad_crc == 0);
    CHECK(d.stats.unsupported == 0);
    CHECK(d.stats.skipped_bytes == outside.size());
    CHECK(d.stats.dropped_bytes == 0);
    CHECK(d.buffered == 0);
  }
  // Each packet carries exactly the IMU and Attitude fields of its header, and each parses alone.
  const Vn100Decoded d = decode_stream(raw);
  for (size_t k = 0; k < d.messages.size(); ++k) {
    const auto& m = d.messages[k];
    CHECK(vn100::groups_of(m) == 0x14);
    CHECK(vn100::fields_of(m, vn100::kGroupImu) == 0x003E);
    CHECK(vn100::fields_of(m, vn100::kGroupAttitude) == 0x003A);
    size_t used = 0;
    auto one = vn100::parse_packet(std::span<const uint8_t>(raw).subspan(at[k]), &used);
    REQUIRE(one.ok());
    CHECK(used == kRealPacket);
    CHECK(*one == m);
    CHECK(vn100::encode_packet(m) == Bytes(raw.begin() + static_cast<std::ptrdiff_t>(at[k]),
                                           raw.begin() + static_cast<std::ptrdiff_t>(at[k] + kRealPacket)));
  }
}

TEST_CASE("VN-100 real log equals the logger author's CSV to float32 precision", "[hal]") {
  const Vn100Decoded d = decode_stream(testing::read_file(testing::testdata("vn100/F00294")));
  REQUIRE(d.messages.size() == 99);
  std::ifstream csv(testing::testdata("vn100/F00294_B.csv"));
  std::string line;
  REQUIRE(std::getline(csv, line));
  const auto header = split_csv(line);
  REQUIRE(header.size() == 29);
  CHECK(header.front() == "MagX");
  CHECK(header.back() == "ACCNED3");
  // The names describe() gives the fields are the CSV's (the author wrote ACCNED3 for AccNED3).
  const auto named = vn100::describe(d.messages[0]);
  REQUIRE(named.size() == 29);
  for (size_t c = 0; c < 29; ++c) CHECK(lower(named[c].first) == lower(header[c]));

  size_t row = 0;
  while (std::getline(csv, line)) {
    const auto cells = split_csv(line);
    if (cells.empty()) continue;
    REQUIRE(cells.size() == 29);
    const size_t packet = row < 78 ? row : row + 1;  // packet 78 is not in the CSV (README)
    REQUIRE(packet < d.messages.size());
    const auto v = real_fields(d.messages[packet]);
    for (size_t c = 0; c < 29; ++c) {
      INFO("row " << row << " (packet " << packet << ") column " << header[c]);
      // The CSV prints each float with 7 significant digits: our value printed the same way is
      // the same text, and the two differ by at most half a unit in the 7th digit.
      char mine[32];
      std::snprintf(mine, sizeof mine, "%.6e", static_cast<double>(v[c]));
      CHECK(std::string(mine) == cells[c]);
      const double theirs = std::strtod(cells[c].c_str(), nullptr);
      CHECK(std::abs(theirs - static_cast<double>(v[c])) <= 5.01e-7 * std::abs(theirs) + 1e-30);
    }
    ++row;
  }
  CHECK(row == 98);
}

TEST_CASE("VN-100 real log: DCM and yaw/pitch/roll give the same reading", "[hal]") {
  const Vn100Decoded d = decode_stream(testing::read_file(testing::testdata("vn100/F00294")));
  REQUIRE(d.messages.size() == 99);
  for (const auto& m : d.messages) {
    auto from_dcm = vn100::to_imu_reading(m, Quat::Identity(), Time());  // no quaternion: DCM
    vn100::Message only_ypr = m;
    only_ypr.attitude.dcm.reset();
    auto from_ypr = vn100::to_imu_reading(only_ypr, Quat::Identity(), Time());
    REQUIRE(from_dcm.ok());
    REQUIRE(from_ypr.ok());
    CHECK(from_dcm->q_W_V.angularDistance(from_ypr->q_W_V) < 1e-5);
    // Rates and acceleration from the uncompensated IMU fields (nothing else in this log),
    // FRD -> FLU with the sensor aligned with V.
    const auto& g = *m.imu.uncomp_gyro;
    const auto& a = *m.imu.uncomp_accel;
    CHECK(from_dcm->angular_velocity_V == Vec3(g[0], -static_cast<double>(g[1]), -static_cast<double>(g[2])));
    CHECK(from_dcm->linear_acceleration_V == Vec3(a[0], -static_cast<double>(a[1]), -static_cast<double>(a[2])));
    // AccelNed is the body acceleration rotated by the DCM (body -> NED, row-major).
    const auto& c = *m.attitude.dcm;
    for (size_t i = 0; i < 3; ++i) {
      const double ned = c[3 * i] * a[0] + c[3 * i + 1] * a[1] + c[3 * i + 2] * a[2];
      CHECK(ned == Approx((*m.attitude.accel_ned)[i]).margin(0.02));
    }
  }
}

TEST_CASE("VN-100 orientation from quaternion, DCM or yaw/pitch/roll gives the same reading", "[hal]") {
  const double d2r = M_PI / 180.0;
  const double yaw = 123.0, pitch = -20.0, roll = 35.0;
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(yaw * d2r, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch * d2r, Vec3::UnitY()) *
                             Eigen::AngleAxisd(roll * d2r, Vec3::UnitX()))
                                .toRotationMatrix();
  const Quat q(R);
  vn100::Message base;
  base.angular_rate = vn100::Float3{0.1f, -0.2f, 0.3f};
  base.accel = vn100::Float3{0.5f, 0.25f, -9.8f};
  std::vector<std::pair<std::string, vn100::Message>> sources;
  auto add = [&](const std::string& name, auto set) {
    vn100::Message m = base;
    set(m);
    sources.emplace_back(name, m);
  };
  const std::array<float, 4> xyzw = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                                     static_cast<float>(q.w())};
  std::array<float, 9> dcm{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) dcm[static_cast<size_t>(3 * i + j)] = static_cast<float>(R(i, j));
  const vn100::Float3 ypr = {static_cast<float>(yaw), static_cast<float>(pitch), static_cast<float>(roll)};
  add("Common quaternion", [&](vn100::Message& m) { m.quat_xyzw = xyzw; });
  add("Attitude quaternion", [&](vn100::Message& m) { m.attitude.quat_xyzw = xyzw; });
  add("Attitude DCM", [&](vn100::Message& m) { m.attitude.dcm = dcm; });
  add("Common YawPitchRoll", [&](vn100::Message& m) { m.ypr_deg = ypr; });
  add("Attitude YawPitchRoll", [&](vn100::Message& m) { m.attitude.ypr_deg = ypr; });
  // The quaternion wins over a disagreeing YawPitchRoll, the DCM over a disagreeing YawPitchRoll.
  add("quaternion over YPR", [&](vn100::Message& m) {
    m.quat_xyzw = xyzw;
    m.attitude.ypr_deg = vn100::Float3{0, 0, 0};
  });
  add("DCM over YPR", [&](vn100::Message& m) {
    m.attitude.dcm = dcm;
    m.ypr_deg = vn100::Float3{0, 0, 0};
  });
  const Quat q_V_S(Eigen::AngleAxisd(0.3, Vec3(0.2, -1, 0.5).normalized()));
  auto reference = vn100::to_imu_reading(sources[0].second, q_V_S, Time::from_ms(5));
  REQUIRE(reference.ok());
  CHECK(q_ned_frd_of(xyzw).angularDistance(q) < 1e-6);
  for (const auto& [name, m] : sources) {
    INFO(name);
    // Through the wire as well: the reading must not depend on the encoding.
    auto wire = vn100::parse_packet(vn100::encode_packet(m));
    REQUIRE(wire.ok());
    auto r = vn100::to_imu_reading(*wire, q_V_S, Time::from_ms(5));
    REQUIRE(r.ok());
    CHECK(r->stamp == Time::from_ms(5));
    CHECK(r->q_W_V.angularDistance(reference->q_W_V) < 1e-6);
    CHECK((r->angular_velocity_V - reference->angular_velocity_V).norm() < 1e-12);
    CHECK((r->linear_acceleration_V - reference->linear_acceleration_V).norm() < 1e-12);
  }
}

TEST_CASE("VN-100 rates and acceleration come from the first field present", "[hal]") {
  vn100::Message m;
  m.attitude.quat_xyzw = std::array<float, 4>{0, 0, 0, 1};
  auto read = [&] {
    auto r = vn100::to_imu_reading(m, Quat::Identity(), Time());
    REQUIRE(r.ok());
    return *r;
  };
  // None: exactly zero (the "no gyro" marker dead reckoning relies on).
  CHECK(read().angular_velocity_V == Vec3::Zero());
  CHECK(read().linear_acceleration_V == Vec3::Zero());
  m.uncomp_imu = vn100::UncompImu{{1, 0, 0}, {0.5f, 0, 0}};
  CHECK(read().angular_velocity_V.x() == 0.5);
  CHECK(read().linear_acceleration_V.x() == 1.0);
  m.imu.uncomp_gyro = vn100::Float3{0.25f, 0, 0};
  m.imu.uncomp_accel = vn100::Float3{2, 0, 0};
  CHECK(read().angular_velocity_V.x() == 0.25);
  CHECK(read().linear_acceleration_V.x() == 2.0);
  m.imu.angular_rate = vn100::Float3{0.125f, 0, 0};
  m.imu.accel = vn100::Float3{3, 0, 0};
  CHECK(read().angular_velocity_V.x() == 0.125);
  CHECK(read().linear_acceleration_V.x() == 3.0);
  m.angular_rate = vn100::Float3{0.0625f, 0.5f, 0.25f};
  m.accel = vn100::Float3{4, 1, -9};
  CHECK(read().angular_velocity_V == Vec3(0.0625, -0.5, -0.25));
  CHECK(read().linear_acceleration_V == Vec3(4, -1, 9));
}

TEST_CASE("VN-100 errors name what the packet lacks", "[hal]") {
  vn100::Message m;
  m.imu.temp_c = 20.0f;
  m.imu.uncomp_gyro = vn100::Float3{0, 0, 0};
  auto r = vn100::to_imu_reading(m, Quat::Identity(), Time());
  REQUIRE_FALSE(r.ok());
  CHECK_THAT(r.error().message,
             Catch::Contains("VN-100 packet has no orientation field (need Quaternion, DCM or YawPitchRoll)"));
  m.attitude.dcm = std::array<float, 9>{1, 0, 0, 0, 1, 0, 0, 0, -1};  // a reflection
  r = vn100::to_imu_reading(m, Quat::Identity(), Time());
  REQUIRE_FALSE(r.ok());
  CHECK_THAT(r.error().message, Catch::Contains("DCM is not a rotation"));
  m.attitude.dcm.reset();
  m.quat_xyzw = std::array<float, 4>{0, 0, 0, 0};
  CHECK_FALSE(vn100::to_imu_reading(m, Quat::Identity(), Time()).ok());
  // A message with no field encodes to groups byte 0, which no VN-100 sends.
  auto empty = vn100::parse_packet(vn100::encode_packet(vn100::Message{}));
  REQUIRE_FALSE(empty.ok());
  CHECK_THAT(empty.error().message, Catch::Contains("no group"));
}

TEST_CASE("VN-100 packet with an unknown group or field bit is unsupported and the stream resyncs", "[hal]") {
  vn100::Message good_m;
  good_m.attitude.ypr_deg = vn100::Float3{10, 2, -3};
  good_m.imu.temp_c = 21.5f;
  const Bytes good = vn100::encode_packet(good_m);
  // Common TimeStartup plus the GNSS group (0x08, VN-200/300) with its TimeUTC field: a valid
  // CRC, but we cannot know the GNSS group's sizes.
  const Bytes gnss = with_crc({0xFA, 0x09, 0x01, 0x00, 0x01, 0x00, 1, 2, 3, 4, 5, 6, 7, 8, 24, 5, 6, 7, 8, 9, 0, 0});
  REQUIRE(std::count(gnss.begin() + 1, gnss.end(), 0xFA) == 0);
  {
    auto one = vn100::parse_packet(gnss);
    REQUIRE_FALSE(one.ok());
    CHECK_THAT(one.error().message, Catch::Contains("group bit 3") && Catch::Contains("GNSS"));
    const Vn100Decoded d = decode_stream(cat({gnss, good}));
    REQUIRE(d.messages.size() == 1);
    CHECK(d.messages[0] == good_m);
    CHECK(d.stats.unsupported == 1);
    CHECK(d.stats.bad_crc == 0);
    CHECK(d.stats.skipped_bytes == gnss.size());
  }
  // Field bits the ICD gives no size for: reserved, undocumented or the extension bit 15.
  struct Case {
    uint8_t group;
    unsigned bit;
  };
  for (const Case c : {Case{vn100::kGroupTime, 10}, Case{vn100::kGroupImu, 12}, Case{vn100::kGroupAttitude, 9},
                       Case{vn100::kGroupAttitude, 11}, Case{vn100::kGroupAttitude, 14},
                       Case{vn100::kGroupCommon, 15}, Case{vn100::kGroupImu, 15}}) {
    INFO("group " << int(c.group) << " bit " << c.bit);
    const uint16_t mask = static_cast<uint16_t>(1u << c.bit);
    const Bytes bad = with_crc({0xFA, c.group, static_cast<uint8_t>(mask & 0xFF), static_cast<uint8_t>(mask >> 8), 0x11,
                                0x22, 0x33, 0x44});
    const auto len = vn100::packet_length(bad);
    CHECK(len.status == vn100::PacketLength::Status::kUnsupported);
    CHECK_THAT(len.reason, Catch::Contains("bit " + std::to_string(c.bit)));
    const Vn100Decoded d = decode_stream(cat({bad, text("M,4240\r\n"), good}), {3});
    REQUIRE(d.messages.size() == 1);
    CHECK(d.messages[0] == good_m);
    CHECK(d.stats.unsupported + d.stats.bad_crc >= 1);
    CHECK(d.stats.unsupported >= 1);
  }
  // Other groups-byte bits: INS, GNSS2, the extension bit 7, and no group at all.
  for (uint8_t g : {uint8_t{0x20}, uint8_t{0x40}, uint8_t{0x80}, uint8_t{0x00}}) {
    INFO("groups " << int(g));
    CHECK(vn100::packet_length(Bytes{0xFA, g, 0x01, 0x00}).status == vn100::PacketLength::Status::kUnsupported);
  }
  // An empty field mask for a present group.
  CHECK(vn100::packet_length(Bytes{0xFA, 0x01, 0x00, 0x00}).status == vn100::PacketLength::Status::kUnsupported);
}

TEST_CASE("VN-100 truncated and CRC-corrupted packets are counted and skipped", "[hal]") {
  vn100::Message a;
  a.time.time_startup_ns = 0x0102030405060708ull;
  a.attitude.ypr_deg = vn100::Float3{45.5f, 1.25f, -2.5f};
  a.imu.temp_c = 19.5f;
  a.imu.pres_kpa = 101.25f;
  vn100::Message b;
  b.quat_xyzw = std::array<float, 4>{0, 0, 0.6f, 0.8f};
  b.angular_rate = vn100::Float3{0.01f, 0.02f, 0.03f};
  const Bytes good_a = vn100::encode_packet(a);
  const Bytes good_b = vn100::encode_packet(b);
  REQUIRE(std::count(good_a.begin() + 1, good_a.end(), 0xFA) == 0);  // no false sync inside
  const Bytes truncated(good_a.begin(), good_a.begin() + 20);
  Bytes corrupt = good_a;
  corrupt[good_a.size() / 2] ^= 0x10;
  REQUIRE(std::count(corrupt.begin() + 1, corrupt.end(), 0xFA) == 0);
  const Bytes ascii = text("M,4240\r\n\r\nB,\n\r\n");

  auto one = vn100::parse_packet(truncated);
  REQUIRE_FALSE(one.ok());
  CHECK_THAT(one.error().message, Catch::Contains("truncated"));
  auto crc = vn100::parse_packet(corrupt);
  REQUIRE_FALSE(crc.ok());
  CHECK_THAT(crc.error().message, Catch::Contains("CRC"));

  // The truncated packet's length is read from its masks; the bytes that follow complete it
  // with the wrong contents, so its CRC fails. Then the corrupted packet, then a good one.
  for (const auto& chunks : {std::vector<size_t>{1u << 20}, std::vector<size_t>{1}, std::vector<size_t>{5, 11}}) {
    const Vn100Decoded d = decode_stream(cat({truncated, ascii, corrupt, good_b}), chunks);
    REQUIRE(d.messages.size() == 1);
    CHECK(d.messages[0] == b);
    CHECK(d.stats.accepted == 1);
    CHECK(d.stats.bad_crc == 2);
    CHECK(d.stats.unsupported == 0);
    CHECK(d.stats.skipped_bytes == truncated.size() + ascii.size() + corrupt.size());
    CHECK(d.buffered == 0);
  }
  // A truncated packet at the end of the stream stays buffered, waiting for its remainder.
  const Vn100Decoded tail = decode_stream(cat({good_b, truncated}));
  CHECK(tail.messages.size() == 1);
  CHECK(tail.buffered == truncated.size());
  CHECK(tail.stats.bad_crc == 0);
}

TEST_CASE("VN-100 stream buffer is bounded", "[hal]") {
  vn100::StreamParser p;
  const Bytes garbage(vn100::StreamParser::kMaxBuffered + 5000, 'A');
  p.push(garbage);
  CHECK(p.buffered() == vn100::StreamParser::kMaxBuffered);
  CHECK(p.stats().dropped_bytes == 5000);
  p.push(Bytes(100, 'B'));
  CHECK(p.buffered() == vn100::StreamParser::kMaxBuffered);
  CHECK(p.stats().dropped_bytes == 5100);
  CHECK_FALSE(p.pop());
  CHECK(p.stats().skipped_bytes == vn100::StreamParser::kMaxBuffered);
  CHECK(p.buffered() == 0);
  // A header announcing the longest packet the masks allow: the parser waits for no more than
  // kMaxPacketBytes, then rejects it.
  Bytes longest = {0xFA, 0x17, 0xFF, 0x7F, 0xFF, 0x03, 0xFF, 0x0F, 0xFF, 0x31};
  const auto len = vn100::packet_length(longest);
  REQUIRE(len.status == vn100::PacketLength::Status::kKnown);
  CHECK(len.bytes == vn100::kMaxPacketBytes);
  longest.resize(vn100::kMaxPacketBytes, 0x00);
  p.push(longest);
  CHECK_FALSE(p.pop());
  CHECK(p.stats().bad_crc == 1);
  CHECK(p.buffered() == 0);
}

namespace {

// Random values for every field type; `bytes` counts the wire size independently of the
// driver's tables. Floats are finite (so Message == compares) unless `any_bits`.
struct Gen {
  bool any_bits = false;
  size_t bytes = 0;
  template <class T>
  void value(T& v) {
    bytes += sizeof(T);
    if constexpr (std::is_floating_point_v<T>) {
      if (any_bits) {
        using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
        const Bits b = *rc::gen::arbitrary<Bits>();
        std::memcpy(&v, &b, sizeof v);
      } else {
        v = static_cast<T>(*rc::gen::inRange(-2000000, 2000000)) / T(1024);
      }
    } else {
      v = *rc::gen::arbitrary<T>();
    }
  }
  template <class T, size_t N>
  void value(std::array<T, N>& a) {
    for (auto& x : a) value(x);
  }
  void value(vn100::UncompImu& s) { value(s.accel), value(s.gyro); }
  void value(vn100::MagPres& s) { value(s.mag), value(s.temp_c), value(s.pres_kpa); }
  void value(vn100::Deltas& s) { value(s.dtime_s), value(s.dtheta_deg), value(s.dvel_mps); }
  void value(vn100::DeltaTheta& s) { value(s.dtime_s), value(s.dtheta_deg); }
  void value(vn100::Heave& s) { value(s.heave_m), value(s.heave_rate_mps), value(s.delayed_heave_m); }
  void value(vn100::TimeUtc& s) {
    value(s.year), value(s.month), value(s.day), value(s.hour), value(s.minute), value(s.second), value(s.ms);
  }
  template <class T>
  void maybe(bool group_on, std::optional<T>& o) {
    if (group_on && *rc::gen::arbitrary<bool>()) value(o.emplace());
  }
};

vn100::Message random_message(Gen& g) {
  vn100::Message m;
  const bool c = *rc::gen::arbitrary<bool>(), t = *rc::gen::arbitrary<bool>(), i = *rc::gen::arbitrary<bool>(),
             a = *rc::gen::arbitrary<bool>();
  g.maybe(c, m.time_startup_ns), g.maybe(c, m.time_gps_ns), g.maybe(c, m.time_syncin_ns), g.maybe(c, m.ypr_deg);
  g.maybe(c, m.quat_xyzw), g.maybe(c, m.angular_rate), g.maybe(c, m.position_lla), g.maybe(c, m.velocity_ned);
  g.maybe(c, m.accel), g.maybe(c, m.uncomp_imu), g.maybe(c, m.mag_pres), g.maybe(c, m.deltas);
  g.maybe(c, m.ins_status), g.maybe(c, m.sync_in_cnt), g.maybe(c, m.time_gps_pps_ns);
  auto& tm = m.time;
  g.maybe(t, tm.time_startup_ns), g.maybe(t, tm.time_gps_ns), g.maybe(t, tm.gps_tow_ns), g.maybe(t, tm.gps_week);
  g.maybe(t, tm.time_syncin_ns), g.maybe(t, tm.time_gps_pps_ns), g.maybe(t, tm.time_utc), g.maybe(t, tm.sync_in_cnt);
  g.maybe(t, tm.sync_out_cnt), g.maybe(t, tm.time_status);
  auto& im = m.imu;
  g.maybe(i, im.imu_status), g.maybe(i, im.uncomp_mag), g.maybe(i, im.uncomp_accel), g.maybe(i, im.uncomp_gyro);
  g.maybe(i, im.temp_c), g.maybe(i, im.pres_kpa), g.maybe(i, im.delta_theta), g.maybe(i, im.delta_vel_mps);
  g.maybe(i, im.mag), g.maybe(i, im.accel), g.maybe(i, im.angular_rate), g.maybe(i, im.sens_sat);
  auto& at = m.attitude;
  g.maybe(a, at.vpe_status), g.maybe(a, at.ypr_deg), g.maybe(a, at.quat_xyzw), g.maybe(a, at.dcm);
  g.maybe(a, at.mag_ned), g.maybe(a, at.accel_ned), g.maybe(a, at.linear_accel_body), g.maybe(a, at.linear_accel_ned);
  g.maybe(a, at.ypr_u_deg), g.maybe(a, at.heave), g.maybe(a, at.att_u_deg);
  return m;
}

}  // namespace

TEST_CASE("VN-100 random group and field selections round-trip", "[hal][rapidcheck]") {
  rc::prop("encode then decode gives the same fields, through a stream with ASCII between packets", [] {
    Gen g;
    g.any_bits = *rc::gen::arbitrary<bool>();
    const vn100::Message m = random_message(g);
    RC_PRE(vn100::groups_of(m) != 0);
    const Bytes wire = vn100::encode_packet(m);
    size_t n_groups = 0;
    for (uint8_t grp : {vn100::kGroupCommon, vn100::kGroupTime, vn100::kGroupImu, vn100::kGroupAttitude})
      n_groups += vn100::fields_of(m, grp) != 0;
    RC_ASSERT(wire.size() == 1 + 1 + 2 * n_groups + g.bytes + 2);
    RC_ASSERT(wire.size() <= vn100::kMaxPacketBytes);
    const auto len = vn100::packet_length(wire);
    RC_ASSERT(len.status == vn100::PacketLength::Status::kKnown);
    RC_ASSERT(len.bytes == wire.size());
    size_t used = 0;
    auto back = vn100::parse_packet(wire, &used);
    RC_ASSERT(back.ok());
    RC_ASSERT(used == wire.size());
    RC_ASSERT(vn100::encode_packet(*back) == wire);
    RC_ASSERT(vn100::describe(*back) == vn100::describe(m));
    if (!g.any_bits) RC_ASSERT(*back == m);
    for (uint8_t grp : {vn100::kGroupCommon, vn100::kGroupTime, vn100::kGroupImu, vn100::kGroupAttitude})
      RC_ASSERT(vn100::fields_of(*back, grp) == vn100::fields_of(m, grp));

    // The same packet twice between logger-style ASCII lines, pushed in random chunks.
    const Bytes ascii1 = text("$GPRMC,000012.800,V,,,,,0.00,0.00,060180,,,N*49\r\nM,4169\r\n\r\nB,\n\r\n");
    const Bytes ascii2 = text("\nM,4240\r\n\r\nB,\n\r\n");
    const Bytes stream = cat({ascii1, wire, ascii2, wire, ascii2});
    vn100::StreamParser p;
    size_t at = 0, accepted_bytes = 0, n = 0;
    while (at < stream.size()) {
      const size_t k = std::min<size_t>(*rc::gen::inRange<size_t>(1, 200), stream.size() - at);
      p.push(std::span<const uint8_t>(stream).subspan(at, k));
      at += k;
      while (auto q = p.pop()) {
        RC_ASSERT(vn100::encode_packet(*q) == wire);
        accepted_bytes += wire.size();
        ++n;
      }
    }
    RC_ASSERT(n == 2u);
    RC_ASSERT(p.stats().bad_crc == 0u);
    RC_ASSERT(p.stats().unsupported == 0u);
    RC_ASSERT(p.stats().skipped_bytes == ascii1.size() + 2 * ascii2.size());
    RC_ASSERT(accepted_bytes + p.stats().skipped_bytes + p.buffered() == stream.size());
  });
}

TEST_CASE("VN-100 describe lists every field with full precision", "[hal]") {
  vn100::Message m;
  m.time_startup_ns = 123456789012ull;
  m.ypr_deg = vn100::Float3{0.1f, -0.2f, 179.99f};
  m.position_lla = std::array<double, 3>{59.91234567890123, 10.75, -3.5};
  m.time.time_utc = vn100::TimeUtc{24, 6, 30, 23, 59, 58, 999};
  m.imu.temp_c = 19.455678f;
  m.attitude.heave = vn100::Heave{0.5f, -0.25f, 0.125f};
  const auto d = vn100::describe(m);
  std::vector<std::string> names;
  for (const auto& [name, value] : d) names.push_back(name);
  CHECK(names == std::vector<std::string>{"Common.TimeStartup", "Common.Yaw", "Common.Pitch", "Common.Roll",
                                          "Common.Latitude", "Common.Longitude", "Common.Altitude", "UtcYear",
                                          "UtcMonth", "UtcDay", "UtcHour", "UtcMinute", "UtcSecond", "UtcMs", "Temp",
                                          "Heave", "HeaveRate", "DelayedHeave"});
  CHECK(d[0].second == "123456789012");
  CHECK(std::strtof(d[1].second.c_str(), nullptr) == 0.1f);
  CHECK(std::strtof(d[3].second.c_str(), nullptr) == 179.99f);
  CHECK(std::strtod(d[4].second.c_str(), nullptr) == 59.91234567890123);
  CHECK(d[7].second == "24");
  CHECK(d[13].second == "999");
  CHECK(std::strtof(d[14].second.c_str(), nullptr) == 19.455678f);
}
