#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <thread>

#include "hal/drivers/device_config.hpp"
#include "hal/drivers/driver_device.hpp"
#include "hal/drivers/emulator.hpp"
#include "hal/drivers/protocol_decoder.hpp"
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/drivers/test_support.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace rti_test {

// CRC-16/XMODEM straight from its definition, bit by bit (poly 0x1021, init 0, MSB first).
uint16_t crc_bitwise(std::span<const uint8_t> d) {
  uint16_t crc = 0;
  for (uint8_t b : d) {
    crc = static_cast<uint16_t>(crc ^ (b << 8));
    for (int i = 0; i < 8; ++i) crc = static_cast<uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
  }
  return crc;
}

Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }

rti::Ensemble sample(uint32_t number, uint32_t beams = 4) {
  rti::Ensemble e;
  e.number = number;
  rti::EnsembleData d;
  d.ensemble_number = static_cast<int32_t>(number);
  d.bins = 30;
  d.beams = static_cast<int32_t>(beams);
  d.desired_pings = d.actual_pings = 2;
  d.status = 0x0120;
  d.year = 2019, d.month = 3, d.day = 9, d.hour = 12, d.minute = 23, d.second = 24, d.hundredths = 33;
  d.serial = "01300000000000000000000000000123";
  d.firmware = std::array<uint8_t, 4>{5, 11, 2, 'A'};
  d.subsystem_config = 3;
  e.ensemble_data = d;
  rti::BottomTrack bt;
  bt.first_ping_time_s = 12.5f, bt.last_ping_time_s = 12.75f, bt.heading_deg = 152.25f;
  bt.speed_of_sound_mps = 1500.0f, bt.status = 0x0002, bt.beams = beams, bt.actual_pings = 23;
  for (uint32_t b = 0; b < beams; ++b) {
    bt.range_m[b] = 10.0f + 0.5f * static_cast<float>(b);
    bt.snr_db[b] = 30.0f + static_cast<float>(b);
    bt.beam_velocity_mps[b] = 0.1f * static_cast<float>(b);
    bt.instrument_velocity_mps[b] = b == 0 ? 0.5f : b == 1 ? -0.25f : b == 2 ? 0.125f : 0.0078125f;
    bt.earth_velocity_mps[b] = rti::kBadVelocity;
  }
  e.bottom_track = bt;
  return e;
}

struct Decoded {
  std::vector<rti::Ensemble> ensembles;
  rti::StreamStats stats;
};

Decoded decode_in_pieces(std::span<const uint8_t> in, size_t step) {
  rti::StreamParser p;
  Decoded out;
  for (size_t at = 0; at < in.size(); at += step) {
    p.push(in.subspan(at, std::min(step, in.size() - at)));
    while (auto e = p.pop()) out.ensembles.push_back(std::move(*e));
  }
  p.finish();
  while (auto e = p.pop()) out.ensembles.push_back(std::move(*e));
  out.stats = p.stats();
  return out;
}

std::map<std::string, uint64_t> read_expected(const std::string& path) {
  std::map<std::string, uint64_t> m;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq != std::string::npos) m[line.substr(0, eq)] = std::stoull(line.substr(eq + 1));
  }
  return m;
}

}  // namespace rti_test

TEST_CASE("rti crc16 gives the CRC-16/XMODEM check value and equals the bit-wise definition", "[hal][rti]") {
  const Bytes check = rti_test::text("123456789");
  CHECK(rti::crc16(check) == 0x31C3);  // the catalogue's check value for CRC-16/XMODEM
  CHECK(rti::crc16({}) == 0);
  std::mt19937 rng(7);
  for (size_t n = 0; n < 200; ++n) {
    Bytes b(n);
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    REQUIRE(rti::crc16(b) == rti_test::crc_bitwise(b));
    REQUIRE(rti::crc16(b) == vn100::crc16_xmodem(b));  // the VN-100's checksum is the same CRC
  }
}

TEST_CASE("rti encoder writes Rowe's layout and its ensembles round-trip", "[hal][rti]") {
  const rti::Ensemble e = rti_test::sample(2668);
  const Bytes wire = rti::encode_ensemble(e);
  // Header: 16 x 0x80, number and size with their complements; checksum's top bytes are 0.
  for (size_t i = 0; i < 16; ++i) REQUIRE(wire[i] == 0x80);
  ByteReader r(wire, 16);
  CHECK(r.u32() == 2668);
  CHECK(r.u32() == ~uint32_t{2668});
  const uint32_t payload = r.u32();
  CHECK(r.u32() == ~payload);
  REQUIRE(wire.size() == 32 + payload + 4);
  CHECK(wire[wire.size() - 1] == 0);
  CHECK(wire[wire.size() - 2] == 0);
  // Ensemble data first: type 20 (int), 23 values, multiplier 1, image 0, name "E000008\0".
  ByteReader ds(wire, 32);
  CHECK(ds.u32() == 20);
  CHECK(ds.u32() == 23);
  CHECK(ds.u32() == 1);
  CHECK(ds.u32() == 0);
  CHECK(ds.u32() == 8);
  CHECK(std::string(wire.begin() + 52, wire.begin() + 60) == std::string("E000008\0", 8));
  // Bottom track (as rti_python's test_BottomTrack expects): type 10, 74 values for 4 beams.
  ByteReader bt(wire, 32 + 28 + 23 * 4);
  CHECK(bt.u32() == 10);
  CHECK(bt.u32() == 74);
  CHECK(bt.u32() == 1);

  auto back = rti::parse_ensemble(wire);
  REQUIRE(back.ok());
  CHECK(back->number == 2668);
  CHECK(back->payload_bytes == payload);
  CHECK(back->ensemble_data == e.ensemble_data);
  CHECK(back->bottom_track == e.bottom_track);
  REQUIRE(back->data_sets.size() == 2);
  CHECK(back->data_sets[1].name == "E000010");
  CHECK(back->data_sets[1].offset == 32 + 28 + 92);
  CHECK(back->unknown_data_sets == 0);
  CHECK(rti::encode_ensemble(*back) == wire);
  // 13-value ensemble data (before firmware revision D) round-trips too.
  rti::Ensemble old = rti_test::sample(5, 3);
  old.ensemble_data->serial.clear();
  old.ensemble_data->firmware.reset();
  old.ensemble_data->subsystem_config.reset();
  auto old_back = rti::parse_ensemble(rti::encode_ensemble(old));
  REQUIRE(old_back.ok());
  CHECK(old_back->ensemble_data == old.ensemble_data);
  CHECK(old_back->bottom_track == old.bottom_track);
  // Date and time.
  CHECK(*e.ensemble_data->unix_time_ns() == 1552134204330000000);
  rti::EnsembleData bad = *e.ensemble_data;
  bad.month = 13;
  CHECK_FALSE(bad.unix_time_ns().ok());
}

TEST_CASE("rti ensembles written by Python's struct decode to the script's values and counts", "[hal][rti]") {
  // The checked-in stream is what testdata/rti/write_ensembles.py writes: run it again and compare.
  const std::string script = testing::testdata("rti/write_ensembles.py");
  const auto out = testing::test_out("rti_python");
  std::filesystem::create_directories(out);
  const std::string cmd = "/usr/bin/python3 '" + script + "' '" + out.string() + "'";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const Bytes stream = testing::read_file(testing::testdata("rti/python_stream.bin"));
  CHECK(testing::read_file((out / "python_stream.bin").string()) == stream);
  auto want = rti_test::read_expected(testing::testdata("rti/python_stream.expected"));
  CHECK(rti_test::read_expected((out / "python_stream.expected").string()) == want);
  CHECK(rti::crc16(rti_test::text("123456789")) == want["crc.123456789"]);

  for (size_t step : {size_t{1}, size_t{7}, size_t{64}, stream.size()}) {
    INFO("read size " << step);
    const auto d = rti_test::decode_in_pieces(stream, step);
    CHECK(d.stats.ensembles == want["ensembles"]);
    CHECK(d.stats.bad_checksum == want["bad_checksum"]);
    CHECK(d.stats.partial == want["partial"]);
    CHECK(d.stats.malformed == want["malformed"]);
    CHECK(d.stats.unknown_data_sets == want["unknown_data_sets"]);
    CHECK(d.stats.skipped_bytes == want["skipped_bytes"]);
    REQUIRE(d.ensembles.size() == 3);
    // 1001: rev D ensemble data, an amplitude profile skipped, 4-beam bottom track.
    const auto& e1 = d.ensembles[0];
    CHECK(e1.number == 1001);
    REQUIRE(e1.ensemble_data);
    CHECK(e1.ensemble_data->serial == "01300000000000000000000000000123");
    CHECK(e1.ensemble_data->firmware == std::array<uint8_t, 4>{5, 11, 2, 'A'});
    CHECK(e1.ensemble_data->subsystem_config == 3);
    CHECK(*e1.ensemble_data->unix_time_ns() == 1552134204330000000);
    CHECK(e1.unknown_data_sets == 1);
    CHECK(e1.data_sets[1].name == "E000004");
    CHECK(e1.data_sets[1].bytes == 28 + 30 * 4 * 4);
    REQUIRE(e1.bottom_track);
    CHECK(e1.bottom_track->beams == 4);
    CHECK(e1.bottom_track->status == 0x0002);
    CHECK(e1.bottom_track->heading_deg == 152.25f);
    CHECK(e1.bottom_track->earth_velocity_mps[2] == 3.0f);
    CHECK(*e1.bottom_track->instrument_xyz_mps() == Vec3(0.5, -0.25, 0.125));
    CHECK(*e1.bottom_track->mean_range_m() == 10.75);
    // 1002: 13-value ensemble data, ancillary and a byte-typed NMEA data set skipped, 3-beam
    // bottom track of the 10-array layout whose X velocity is bad.
    const auto& e2 = d.ensembles[1];
    CHECK(e2.number == 1002);
    CHECK(e2.ensemble_data->serial.empty());
    CHECK_FALSE(e2.ensemble_data->firmware);
    CHECK(e2.unknown_data_sets == 2);
    CHECK(e2.data_sets[2].name == "E000011");
    CHECK(e2.data_sets[2].bytes == 28 + 45);
    CHECK(e2.bottom_track->beams == 3);
    CHECK_FALSE(e2.bottom_track->instrument_xyz_mps());
    CHECK(*e2.bottom_track->mean_range_m() == 5.5);
    // 1005, after 1004 was cut short: bottom track only.
    const auto& e3 = d.ensembles[2];
    CHECK(e3.number == 1005);
    CHECK_FALSE(e3.ensemble_data);
    CHECK(*e3.bottom_track->instrument_xyz_mps() == Vec3(-1.5, 0.0625, 0.03125));
    CHECK(*e3.bottom_track->mean_range_m() == 7.5);
  }

  // `inspect --protocol rti-ensemble`: offsets, sizes and counts.
  auto dec = make_decoder(Protocol::kRtiEnsemble);
  dec->push(stream);
  std::vector<DecodedMessage> msgs;
  while (auto m = dec->pop()) msgs.push_back(std::move(*m));
  dec->finish();
  while (auto m = dec->pop()) msgs.push_back(std::move(*m));
  REQUIRE(msgs.size() == 3);
  const char* names[] = {"1001", "1002", "1005"};
  for (size_t i = 0; i < 3; ++i) {
    CHECK(msgs[i].type == "ensemble");
    CHECK(msgs[i].offset == want[std::string("offset.") + names[i]]);
    CHECK(msgs[i].size == want[std::string("size.") + names[i]]);
    CHECK(msgs[i].fields[0] == std::pair<std::string, std::string>("ensemble_number", names[i]));
  }
  const auto c = dec->counts();
  CHECK(c.good == 3);
  CHECK(c.bad == 2);  // 1003's checksum, 1004 cut short; 1006 at the end is trailing
  CHECK(c.trailing_bytes == want["trailing_bytes"]);
  CHECK(c.skipped_bytes == want["skipped_bytes"]);
  CHECK(c.last_error.find("1006") != std::string::npos);
}

TEST_CASE("rti unknown data sets are skipped by their declared size", "[hal][rti]") {
  const rti::Ensemble e = rti_test::sample(9);
  std::vector<Bytes> sets;
  Bytes odd(13);
  for (size_t i = 0; i < odd.size(); ++i) odd[i] = static_cast<uint8_t>(0x80 + i);  // sync bytes inside data
  sets.push_back(rti::encode_data_set("E000011", rti::kTypeByte, 13, 1, odd));
  sets.push_back(rti::encode_data_set("R000001", rti::kTypeFloat, 0, 4, {}));
  Bytes profile(4 * 5 * 3, 0x80);
  sets.push_back(rti::encode_data_set("E000001", rti::kTypeFloat, 5, 3, profile));
  sets.push_back(rti::encode(*e.bottom_track));
  sets.push_back(rti::encode_data_set("E000099", 77, 2, 2, Bytes(16, 0xAB)));  // unknown type: 4-byte values
  const Bytes wire = rti::encode_ensemble(9, sets);
  auto got = rti::parse_ensemble(wire);
  REQUIRE(got.ok());
  CHECK(got->unknown_data_sets == 4);
  CHECK(got->bottom_track == e.bottom_track);
  REQUIRE(got->data_sets.size() == 5);
  CHECK(got->data_sets[0].bytes == 28 + 13);
  CHECK(got->data_sets[4].name == "E000099");
  CHECK_FALSE(got->data_sets[4].decoded);
  CHECK(got->data_sets[3].decoded);
}

TEST_CASE("rti stream resynchronises after garbage and counts bad checksums and partial ensembles", "[hal][rti]") {
  const Bytes a = rti::encode_ensemble(rti_test::sample(1)), b = rti::encode_ensemble(rti_test::sample(2)), c = rti::encode_ensemble(rti_test::sample(3));
  Bytes bad = rti::encode_ensemble(rti_test::sample(4));
  bad[100] ^= 0x40;
  Bytes stream = rti_test::text("$GPGGA,1*00\r\n");
  stream.insert(stream.end(), 15, 0x80);  // a sync run one byte short
  stream.push_back(0x00);
  stream.insert(stream.end(), a.begin(), a.end());
  Bytes fake(32, 0x80);  // 16 x 0x80 with complements that disagree
  stream.insert(stream.end(), fake.begin(), fake.end());
  stream.insert(stream.end(), bad.begin(), bad.end());
  stream.insert(stream.end(), b.begin(), b.begin() + 200);  // cut short by c
  stream.insert(stream.end(), c.begin(), c.end());
  stream.insert(stream.end(), a.begin(), a.begin() + 40);  // the end of the stream inside an ensemble
  const auto whole = rti_test::decode_in_pieces(stream, stream.size());
  for (size_t step : {size_t{1}, size_t{3}, size_t{17}, size_t{4096}}) {
    const auto d = rti_test::decode_in_pieces(stream, step);
    CHECK(d.stats.ensembles == whole.stats.ensembles);
    CHECK(d.stats.skipped_bytes == whole.stats.skipped_bytes);
    CHECK(d.ensembles == whole.ensembles);
  }
  REQUIRE(whole.ensembles.size() == 2);
  CHECK(whole.ensembles[0].number == 1);
  CHECK(whole.ensembles[1].number == 3);
  CHECK(whole.stats.bad_checksum == 1);
  CHECK(whole.stats.partial == 2);
  CHECK(whole.stats.malformed == 0);
  CHECK(whole.stats.skipped_bytes == 13 + 16 + 32 + bad.size() + 200);

  // A complete ensemble cut by nothing but whose checksum fails at the very end of the stream.
  const auto last = rti_test::decode_in_pieces(bad, 5);
  CHECK(last.stats.bad_checksum == 1);
  CHECK(last.stats.skipped_bytes == bad.size());
  // A header declaring more than kMaxPayloadBytes is not a header.
  Bytes huge = rti::encode_ensemble(rti_test::sample(6));
  ByteWriter(huge).patch_u32(24, rti::kMaxPayloadBytes + 1);
  ByteWriter(huge).patch_u32(28, ~(rti::kMaxPayloadBytes + 1));
  CHECK_FALSE(rti::parse_header(huge));
}

TEST_CASE("rti ensembles with a good checksum but broken data sets are malformed, naming the data set", "[hal][rti]") {
  Bytes set = rti::encode(*rti_test::sample(1).bottom_track);
  ByteWriter(set).patch_u32(4, 1000);  // elements: far beyond the payload
  const Bytes wire = rti::encode_ensemble(1, std::vector<Bytes>{set});
  auto r = rti::parse_ensemble(wire);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message.find("data set at byte 32") != std::string::npos);
  CHECK(r.error().message.find("E000010") != std::string::npos);
  const auto d = rti_test::decode_in_pieces(wire, 9);
  CHECK(d.stats.malformed == 1);
  CHECK(d.stats.skipped_bytes == wire.size());

  Bytes beams = rti::encode(*rti_test::sample(1).bottom_track);
  ByteWriter w(beams);
  const float seventeen = 17.0f;
  uint32_t bits;
  std::memcpy(&bits, &seventeen, 4);
  w.patch_u32(28 + 12 * 4, bits);
  auto r2 = rti::parse_ensemble(rti::encode_ensemble(2, std::vector<Bytes>{beams}));
  REQUIRE_FALSE(r2.ok());
  CHECK(r2.error().message.find("number of beams 17") != std::string::npos);
  auto r3 = rti::parse_ensemble(rti::encode_ensemble(3, std::vector<Bytes>{Bytes(12, 0)}));
  REQUIRE_FALSE(r3.ok());
  CHECK(r3.error().message.find("needs 20 bytes") != std::string::npos);
}

TEST_CASE("rti bottom track becomes a DvlReading in V through the mounting, as $PRTI01 does", "[hal][rti]") {
  const Quat q_V_D(Eigen::AngleAxisd(0.5, Vec3::UnitZ()) * Eigen::AngleAxisd(3.14159265358979323846, Vec3::UnitX()));
  rti::Ensemble e = rti_test::sample(1);
  auto r = rti::to_dvl_reading(e, q_V_D, Time::from_ms(5));
  REQUIRE(r);
  CHECK(r->valid);
  CHECK(r->stamp == Time::from_ms(5));
  CHECK((r->velocity_V_mps - q_V_D * Vec3(0.5, -0.25, 0.125)).norm() < 1e-12);
  CHECK(r->altitude_m == Approx(10.75));
  // Same as the $PRTI01 path with the same instrument velocity and depth.
  dvl::DvlVelocity v;
  v.valid = true;
  v.velocity_D_mps = Vec3(0.5, -0.25, 0.125);
  v.altitude_m = 10.75;
  CHECK(*r == dvl::to_dvl_reading(v, q_V_D, Time::from_ms(5)));

  e.bottom_track->instrument_velocity_mps[1] = rti::kBadVelocity;
  e.bottom_track->range_m[0] = e.bottom_track->range_m[1] = e.bottom_track->range_m[2] = 0.0f;
  r = rti::to_dvl_reading(e, q_V_D, Time());
  REQUIRE(r);
  CHECK_FALSE(r->valid);
  CHECK(r->altitude_m <= 0.0);  // one good range: unknown (Rowe needs two)
  e.bottom_track->beams = 1;
  CHECK_FALSE(e.bottom_track->instrument_xyz_mps());
  e.bottom_track.reset();
  CHECK_FALSE(rti::to_dvl_reading(e, q_V_D, Time()));
}

TEST_CASE("rti emulator ensembles reach a live rti-ensemble device as the fixture's DVL readings", "[hal][rti]") {
  std::vector<Event> mission;
  for (int i = 0; i < 5; ++i) {
    DvlReading d;
    d.stamp = Time::from_ms(100 * i);
    d.velocity_V_mps = Vec3(0.25 * i, -0.5, 0.125);
    d.valid = i != 2;
    d.altitude_m = i == 3 ? -1.0 : 4.5;
    mission.push_back({d.stamp, Channel::kDvl, static_cast<uint64_t>(i), d});
  }
  EmulatorOptions eo;
  eo.dvl_rti_ensemble = true;
  eo.rate = 4.0;
  MissionEmulator emu(mission, eo);
  REQUIRE(emu.start().ok());
  const LiveConfig lc = emu.live_config();
  REQUIRE(lc.devices.size() == 1);
  CHECK(lc.devices[0].kind == DeviceKind::kRtiEnsemble);
  DriverDevice dev(lc.devices[0], ReconnectPolicy{});
  REQUIRE(dev.connect().ok());
  std::vector<Payload> got;
  for (int i = 0; i < 400 && got.size() < mission.size(); ++i) {
    dev.wait(std::chrono::milliseconds(10));
    auto r = dev.read();
    if (!r) break;
    for (auto& p : *r) got.push_back(std::move(p));
  }
  REQUIRE(got.size() == mission.size());
  for (size_t i = 0; i < got.size(); ++i) {
    const auto& want = std::get<DvlReading>(mission[i].payload);
    const auto& r = std::get<DvlReading>(got[i]);
    CHECK(r.valid == want.valid);
    if (want.valid) CHECK((r.velocity_V_mps - want.velocity_V_mps).norm() < 1e-6);  // float32 on the wire
    if (want.altitude_m > 0) CHECK(r.altitude_m == Approx(want.altitude_m));
    else CHECK(r.altitude_m <= 0.0);
  }
  CHECK(dev.health().messages_ok == mission.size());
  CHECK(dev.health().messages_malformed == 0);
}

TEST_CASE("devices.yaml accepts the rti-ensemble DVL kind", "[hal][rti]") {
  auto c = parse_live_config("devices:\n  - {name: dvl, kind: rti-ensemble, serial: /dev/ttyUSB1, baud: 115200, mount_rpy_deg: [0, 0, 90]}\n");
  REQUIRE(c.ok());
  REQUIRE(c->devices.size() == 1);
  CHECK(c->devices[0].kind == DeviceKind::kRtiEnsemble);
  CHECK((c->devices[0].q_V_S * Vec3::UnitX() - Vec3::UnitY()).norm() < 1e-12);
  const std::string yaml = to_yaml(*c);
  CHECK(yaml.find("kind: rti-ensemble") != std::string::npos);
  auto again = parse_live_config(yaml);
  REQUIRE(again.ok());
  CHECK(again->devices[0].kind == DeviceKind::kRtiEnsemble);
  CHECK(protocol_from_name("rti-ensemble").ok());
  CHECK(std::string(protocol_name(Protocol::kRtiEnsemble)) == "rti-ensemble");
}
