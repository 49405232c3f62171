#include <catch2/catch.hpp>
#include <cmath>

#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

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
  CHECK(vn100::crc16_xmodem(std::span<const uint8_t>(wire).subspan(1)) == 0);
  auto back = vn100::parse_packet(wire);
  REQUIRE(back.ok());
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
}

TEST_CASE("A50 velocity reports parse and rotate into V", "[hal]") {
  const std::string line =
      R"({"time": 106.3, "vx": 0.5, "vy": 0.1, "vz": -0.02, "fom": 0.0019, "altitude": 3.4, "velocity_valid": true, "status": 0, "format": "json_v3.1", "type": "velocity"})";
  auto v = dvl::parse_a50_line(line);
  REQUIRE(v.ok());
  REQUIRE(v->has_value());
  const DvlReading r = dvl::to_dvl_reading(**v, dvl::default_a50_mount(), Time::from_ms(9));
  CHECK(r.velocity_V_mps.x() == Approx(0.5));
  CHECK(r.velocity_V_mps.y() == Approx(-0.1));
  CHECK(r.velocity_V_mps.z() == Approx(0.02));
  CHECK(r.altitude_m == 3.4);
  CHECK(r.valid);
  auto other = dvl::parse_a50_line(R"({"type": "position_local", "x": 1})");
  REQUIRE(other.ok());
  CHECK_FALSE(other->has_value());
  CHECK_FALSE(dvl::parse_a50_line("{\"type\": \"velocity\", \"vx\": 1}").ok());
  CHECK_FALSE(dvl::parse_a50_line("not json").ok());
  auto enc = dvl::parse_a50_line(dvl::encode_a50_velocity(**v, 1.0));
  REQUIRE(enc.ok());
  CHECK((*enc)->velocity_D_mps == (*v)->velocity_D_mps);
}

TEST_CASE("PRTI01 sentences parse with checksum and invalid markers", "[hal]") {
  dvl::DvlVelocity v;
  v.valid = true;
  v.velocity_D_mps = Vec3(-1.205, -0.024, -0.347);
  v.altitude_m = 79.38;
  const std::string s = dvl::encode_prti01(v, 8, 380250);
  CHECK(s.rfind("$PRTI01,380250,8,1464,-1205,-24,-347,79380,,,,,0004*", 0) == 0);
  auto back = dvl::parse_prti01(s);
  REQUIRE(back.ok());
  CHECK(back->velocity_D_mps == v.velocity_D_mps);
  CHECK(back->altitude_m == 79.38);
  std::string corrupt = s;
  corrupt[10] = '9';
  CHECK_FALSE(dvl::parse_prti01(corrupt).ok());
  v.valid = false;
  auto inv = dvl::parse_prti01(dvl::encode_prti01(v, 9, 1));
  REQUIRE(inv.ok());
  CHECK_FALSE(inv->valid);
}

TEST_CASE("depth lines parse in both forms", "[hal]") {
  auto d = dvl::parse_depth_line(dvl::encode_depth_line(3.25));
  REQUIRE(d.ok());
  CHECK(*d == 3.25);
  CHECK(*dvl::parse_depth_line(R"({"type":"depth","depth":2.5})") == 2.5);
  CHECK_FALSE(dvl::parse_depth_line("$DEPTH,abc*00").ok());
}

TEST_CASE("line framer splits and bounds lines", "[hal]") {
  LineFramer f(16);
  const std::string s = "abc\r\n0123456789abcdefXYZ\nok\n";
  f.push(as_bytes(s));
  CHECK(*f.pop() == "abc");
  CHECK(*f.pop() == "ok");
  CHECK_FALSE(f.pop());
  CHECK(f.overlong() == 1);
}
