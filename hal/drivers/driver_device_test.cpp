#include <catch2/catch.hpp>
#include <fcntl.h>
#include <stdlib.h>
#include <string>
#include <thread>
#include <utility>
#include <vector>
#include <unistd.h>

#include "hal/drivers/driver_device.hpp"
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/test_support.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace {

// Reads from the device until `want` payloads arrived or ~3 s passed.
std::vector<Payload> read_until(DriverDevice& dev, size_t want) {
  std::vector<Payload> got;
  for (int i = 0; i < 300 && got.size() < want; ++i) {
    dev.wait(std::chrono::milliseconds(10));
    auto r = dev.read();
    if (!r) break;
    for (auto& p : *r) got.push_back(std::move(p));
  }
  return got;
}

}  // namespace

TEST_CASE("malformed packets are counted and skipped on a live link", "[hal]") {
  auto listener = tcp_listen("127.0.0.1", 0);
  REQUIRE(listener.ok());
  DeviceConfig c;
  c.name = "dvl";
  c.kind = DeviceKind::kPrti01;
  c.port = local_port(*listener);
  DriverDevice dev(c, ReconnectPolicy{});
  std::thread server([&] {
    auto client = tcp_accept(*listener, std::chrono::milliseconds(3000));
    if (!client || !client->valid()) return;
    dvl::DvlVelocity v;
    v.valid = true;
    v.velocity_D_mps = Vec3(0.5, 0.0, 0.0);
    std::string stream = dvl::encode_prti01(v, 1, 100);
    stream += "$PRTI01,garbage*00\r\n";
    stream += std::string(5000, 'x') + "\n";  // an over-long line
    std::string bad = dvl::encode_prti01(v, 2, 200);
    bad[12] = bad[12] == '1' ? '2' : '1';  // checksum no longer matches
    stream += bad;
    stream += dvl::encode_prti01(v, 3, 300);
    (void)write_all(*client, as_bytes(stream), std::chrono::milliseconds(2000));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  });
  REQUIRE(dev.connect().ok());
  const auto got = read_until(dev, 2);
  server.join();
  REQUIRE(got.size() == 2);
  CHECK(std::get<DvlReading>(got[0]).velocity_V_mps.x() == 0.5);
  const hal::DeviceHealth h = dev.health();
  CHECK(h.messages_ok == 2);
  CHECK(h.messages_malformed == 3);
  CHECK_FALSE(h.last_error.empty());
}

TEST_CASE("oculus driver discovers the sonar from its status and sends the configured fire message", "[hal]") {
  auto listener = tcp_listen("127.0.0.1", 0);
  REQUIRE(listener.ok());
  DeviceConfig c;
  c.name = "sonar_v";
  c.kind = DeviceKind::kOculus;
  c.address = "auto";
  c.port = local_port(*listener);
  c.mount = SonarMount::kVertical;
  c.part_number = 0;
  c.status_port = 0;  // ephemeral (test)
  c.fire_version = 1;
  c.fire.range = 12.0;
  c.fire.gain_percent = 35.0;
  DriverDevice dev(c, ReconnectPolicy{50, 200, 1000, 5000});
  REQUIRE(dev.listen_status().ok());
  const uint16_t status_port = dev.status_port();
  REQUIRE(status_port != 0);
  std::optional<oculus::FireMessage> fire_seen;
  std::thread sonar([&] {
    auto udp = udp_socket();
    oculus::StatusMessage st;
    st.part_number = kPartM1200d;
    st.device_id = 42;
    (void)udp_send_to(*udp, "127.0.0.1", status_port, oculus::encode_status(st));
    auto client = tcp_accept(*listener, std::chrono::milliseconds(3000));
    if (!client || !client->valid()) return;
    oculus::StreamParser parser;
    std::array<uint8_t, 512> buf;
    for (int i = 0; i < 100 && !fire_seen; ++i) {
      if (!wait_readable(*client, std::chrono::milliseconds(20))) continue;
      auto n = read_some(*client, buf);
      if (!n || *n == 0) return;
      parser.push(std::span<const uint8_t>(buf.data(), *n));
      while (auto m = parser.pop())
        if (auto* f = std::get_if<oculus::FireMessage>(&*m)) fire_seen = *f;
    }
    const SonarPing p = testing::small_ping(SonarMount::kVertical, 5, Time(), 8, 6);
    Bytes wire = {0xde, 0xad, 0x53};  // garbage first: the driver resynchronises
    const Bytes ping = oculus::encode_ping_result(oculus::ping_result_from(p, 2, 42));
    wire.insert(wire.end(), ping.begin(), ping.end());
    (void)write_all(*client, wire, std::chrono::milliseconds(2000));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  });
  Status connected = dev.connect();
  const auto got = connected.ok() ? read_until(dev, 1) : std::vector<Payload>{};
  sonar.join();
  REQUIRE(connected.ok());
  REQUIRE(fire_seen.has_value());
  CHECK(fire_seen->header.msg_version == 1);
  CHECK(fire_seen->config.range == 12.0);
  CHECK(fire_seen->config.gain_percent == 35.0);
  REQUIRE(got.size() == 1);
  const auto& ping = std::get<SonarPing>(got[0]);
  CHECK(ping.part_number == kPartM1200d);
  CHECK(ping.mount == SonarMount::kVertical);
  CHECK(ping.ping_id == 5);
  CHECK(ping.rows == 8);
  CHECK(dev.health().messages_malformed == 0);
}

TEST_CASE("vn100 over a serial port (pseudo-terminal)", "[hal]") {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  REQUIRE(master >= 0);
  Fd m(master);
  REQUIRE(::grantpt(master) == 0);
  REQUIRE(::unlockpt(master) == 0);
  DeviceConfig c;
  c.name = "imu";
  c.kind = DeviceKind::kVn100;
  c.serial_path = ::ptsname(master);
  c.baud = 115200;
  DriverDevice dev(c, ReconnectPolicy{});
  REQUIRE(dev.connect().ok());
  ImuReading r;
  r.q_W_V = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  Bytes wire;
  for (int i = 0; i < 3; ++i) {
    const Bytes b = vn100::encode_packet(vn100::message_from(r, Quat::Identity()));
    wire.insert(wire.end(), b.begin(), b.end());
  }
  REQUIRE(::write(master, wire.data(), wire.size()) == static_cast<ssize_t>(wire.size()));
  const auto got = read_until(dev, 3);
  REQUIRE(got.size() == 3);
  CHECK(std::get<ImuReading>(got[2]).q_W_V.angularDistance(r.q_W_V) < 1e-6);
}

TEST_CASE("devices.yaml parses and round-trips", "[hal]") {
  const std::string text = R"(
queue: {sonar_capacity: 4}
reconnect: {initial_backoff_ms: 50, max_backoff_ms: 800}
devices:
  - {name: sonar_h, kind: oculus, address: 192.168.2.3, mount: horizontal, part_number: 1032,
     fire: {version: 1, range_m: 20, gain_percent: 40, gamma: 150, bits: 16, beams: 256}}
  - {name: imu, kind: vn100, serial: /dev/ttyUSB0, baud: 921600, mount_rpy_deg: [0, 0, 90]}
  - {name: dvl, kind: a50, address: 192.168.194.95, port: 16171}
)";
  auto c = parse_live_config(text);
  REQUIRE(c.ok());
  CHECK(c->queue.sonar_capacity == 4);
  CHECK(c->reconnect.max_backoff_ms == 800);
  REQUIRE(c->devices.size() == 3);
  CHECK(c->devices[0].port == oculus::kTcpPort);
  CHECK(c->devices[0].fire_version == 1);
  CHECK(c->devices[0].fire.gamma == 150);
  CHECK((c->devices[0].fire.flags & oculus::kFlagData16Bit) != 0);
  CHECK((c->devices[0].fire.flags & oculus::kFlag512Beams) == 0);
  CHECK(c->devices[1].serial_path == "/dev/ttyUSB0");
  CHECK(c->devices[1].baud == 921600);
  CHECK(yaw_of(c->devices[1].q_V_S) == Approx(M_PI / 2));
  CHECK(c->devices[2].q_V_S.angularDistance(Quat(0, 1, 0, 0)) < 1e-12);  // A50 default mount
  auto again = parse_live_config(to_yaml(*c));
  REQUIRE(again.ok());
  CHECK(again->devices[0].fire == c->devices[0].fire);
  CHECK_FALSE(parse_live_config("devices: [{name: x, kind: lidar, port: 1}]").ok());
  CHECK_FALSE(parse_live_config("devices: [{name: x, kind: vn100}]").ok());
}

// Issue 35: a misspelt key was ignored and its default kept (a silence timeout of 5 s
// instead of the one meant, an IMU mounted at [0, 0, 0]); each is an error naming the key.
TEST_CASE("devices.yaml rejects unknown keys, naming them, and a non-finite mount", "[hal]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"devices: [{name: d, kind: a50, port: 1}]\nreconect: {max_backoff_ms: 1}\n", "'reconect'"},
      {"queue: {sonar_capacity: 4, nav_capacty: 9}\ndevices: [{name: d, kind: a50, port: 1}]\n", "'nav_capacty' in queue"},
      {"reconnect: {silence_timout_ms: 9}\ndevices: [{name: d, kind: a50, port: 1}]\n", "'silence_timout_ms' in reconnect"},
      {"devices: [{name: imu, kind: vn100, serial: /dev/x, mount_rpy: [0, 0, 90]}]\n", "'mount_rpy' in device 'imu'"},
      {"devices: [{name: imu, kind: vn100, serial: /dev/x, mount: vertical}]\n", "'mount' in device 'imu' (vn100)"},
      {"devices: [{name: s, kind: oculus, fire: {range: 20}}]\n", "'range' in device 's' fire"},
      {"devices: [{name: s, kind: oculus, adress: 10.0.0.1}]\n", "'adress' in device 's'"},
  };
  for (const auto& [text, expected] : cases) {
    INFO(text);
    auto c = parse_live_config(text);
    REQUIRE_FALSE(c.ok());
    CHECK(c.error().message.find("unknown key " + expected) != std::string::npos);
  }
  auto nan = parse_live_config("devices: [{name: imu, kind: vn100, serial: /dev/x, mount_rpy_deg: [0, .nan, 0]}]\n");
  REQUIRE_FALSE(nan.ok());
  CHECK(nan.error().message.find("mount_rpy_deg must be 3 finite numbers") != std::string::npos);
}
