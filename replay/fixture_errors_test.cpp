// Bad input: every fault is an Error naming the file and a byte offset, never a crash.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstring>
#include <limits>

#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/synthetic.hpp"
#include "replay/testing.hpp"

using namespace orthosonar;
using namespace orthosonar::replay;
using namespace orthosonar::replay::testing;

namespace {

SyntheticOptions small() {
  SyntheticOptions so;
  so.duration_ns = 500'000'000;
  return so;
}

std::vector<uint8_t> valid_file(const std::string& path, bool compress = true) {
  WriterOptions o;
  o.compress = compress;
  REQUIRE(write_fixture(path, synthetic_events(5, small()), {{"scene", "x"}}, o).ok());
  return read_bytes(path);
}

uint64_t read_le64(const std::vector<uint8_t>& b, size_t at) {
  uint64_t v = 0;
  for (size_t i = 0; i < 8; ++i) v |= static_cast<uint64_t>(b[at + i]) << (8 * i);
  return v;
}

// Offset of the Data End record (found through the footer).
size_t data_end_offset(const std::vector<uint8_t>& b) {
  const size_t footer = b.size() - 8 - 29;
  return static_cast<size_t>(read_le64(b, footer + 9)) - 13;
}

// Recomputes the data section CRC so a test reaches the check behind it.
void fix_data_crc(std::vector<uint8_t>& b) {
  const size_t de = data_end_offset(b);
  const uint32_t crc = mcap::crc32(0, b.data(), de);
  for (size_t i = 0; i < 4; ++i) b[de + 9 + i] = static_cast<uint8_t>(crc >> (8 * i));
}

// The first chunk record's offset.
size_t first_chunk(const std::vector<uint8_t>& b) {
  size_t pos = 8;
  while (b[pos] != 0x06) pos += 9 + static_cast<size_t>(read_le64(b, pos + 1));
  return pos;
}

std::string expect_error(const std::string& path, const std::vector<uint8_t>& bytes) {
  write_bytes(path, bytes);
  const auto back = read_fixture(path);
  INFO("events read: " << back.events.size());
  REQUIRE_FALSE(back.error.empty());
  CHECK(back.error.find(path) != std::string::npos);
  CHECK(back.error.find("offset") != std::string::npos);
  return back.error;
}

}  // namespace

TEST_CASE("bad input wrong magic", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  b[1] = 'X';
  CHECK(expect_error(dir + "/magic.mcap", b).find("bad magic at byte offset 0") != std::string::npos);
  CHECK_FALSE(expect_error(dir + "/empty.mcap", {}).empty());
}

TEST_CASE("bad input unsupported version", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  b[5] = '1';
  CHECK(expect_error(dir + "/version.mcap", b).find("unsupported MCAP version '1' at byte offset 5") !=
        std::string::npos);
}

TEST_CASE("bad input unsupported opcode", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  const size_t second = 8 + 9 + static_cast<size_t>(read_le64(b, 9));
  b[second] = 0x33;
  CHECK(expect_error(dir + "/opcode.mcap", b).find("opcode 0x33 at byte offset " + std::to_string(second)) !=
        std::string::npos);
}

TEST_CASE("bad input data section CRC mismatch", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  b[first_chunk(b) + 200] ^= 0x01;
  CHECK(expect_error(dir + "/datacrc.mcap", b).find("data section CRC mismatch") != std::string::npos);
}

TEST_CASE("bad input chunk CRC mismatch", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap", /*compress=*/false);
  const size_t chunk = first_chunk(b);
  b[chunk + 300] ^= 0x40;
  fix_data_crc(b);
  CHECK(expect_error(dir + "/chunkcrc.mcap", b).find("chunk CRC mismatch") != std::string::npos);
}

TEST_CASE("bad input summary CRC mismatch", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  b[data_end_offset(b) + 13 + 20] ^= 0x01;
  const auto e = expect_error(dir + "/sumcrc.mcap", b);
  INFO(e);
  CHECK(e.find("summary CRC mismatch") != std::string::npos);
}

TEST_CASE("bad input truncated chunk records", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap", /*compress=*/false);
  const size_t chunk = first_chunk(b);
  // Chunk body: start, end, uncompressed size, crc, compression "" (4), records length.
  const size_t crc_at = chunk + 9 + 24;
  std::fill(b.begin() + static_cast<long>(crc_at), b.begin() + static_cast<long>(crc_at) + 4, uint8_t{0});
  const size_t first_record = crc_at + 4 + 4 + 8;
  b[first_record + 1 + 4] = 0x7f;  // the first inner record now claims far more bytes than the chunk holds
  fix_data_crc(b);
  CHECK(expect_error(dir + "/innertrunc.mcap", b).find("runs past the end of the chunk") != std::string::npos);
}

TEST_CASE("a file cut inside a chunk is recovered up to the previous record", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  const size_t chunk = first_chunk(b);
  b.resize(chunk + 100);
  write_bytes(dir + "/cut.mcap", b);
  const auto back = read_fixture(dir + "/cut.mcap");
  REQUIRE(back.error.empty());
  CHECK(back.events.empty());
  CHECK_FALSE(back.recovery.complete);
  CHECK(back.recovery.bytes_recovered == chunk);
  CHECK(back.recovery.detail.find(dir + "/cut.mcap") != std::string::npos);
  CHECK(back.recovery.detail.find("byte offset " + std::to_string(chunk)) != std::string::npos);
  CHECK(back.metadata.at("scene") == "x");
}

TEST_CASE("bad input unknown schema", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  auto b = valid_file(dir + "/ok.mcap");
  const std::string name = "orthosonar_msgs/Depth";
  auto it = std::search(b.begin(), b.end(), name.begin(), name.end());
  REQUIRE(it != b.end());
  *(it + 16) = 'X';
  fix_data_crc(b);
  CHECK(expect_error(dir + "/schema.mcap", b).find("unknown schema 'orthosonar_msgs/Xepth'") != std::string::npos);
}

TEST_CASE("bad input out-of-order stamps within a channel", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  std::vector<Event> ev;
  ev.push_back({Time::from_s(1), Channel::kDepth, 0, DepthReading{Time::from_s(1), 1.0}});
  ev.push_back({Time::from_s(3), Channel::kDepth, 1, DepthReading{Time::from_s(3), 1.1}});
  ev.push_back({Time::from_s(2), Channel::kDepth, 2, DepthReading{Time::from_s(2), 1.2}});
  REQUIRE(write_fixture(dir + "/order.mcap", ev).ok());
  const auto back = read_fixture(dir + "/order.mcap");
  REQUIRE_FALSE(back.error.empty());
  CHECK(back.events.size() == 2);
  CHECK(back.error.find(dir + "/order.mcap") != std::string::npos);
  CHECK(back.error.find("out-of-order stamps on /depth") != std::string::npos);
  CHECK(back.error.find("chunk at byte offset") != std::string::npos);
}

// Issue 35: a NaN orientation was replayed as it was and reached dead reckoning's poses
// (then int64(floor(NaN)) voxel keys); it is an error naming the file, offset and field.
TEST_CASE("bad input non-finite IMU orientation", "[unit]") {
  const std::string dir = case_dir("errors", Catch::getResultCapture().getCurrentTestName()).string();
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    std::vector<Event> ev;
    ImuReading good;
    good.stamp = Time::from_s(1);
    ev.push_back({good.stamp, Channel::kImu, 0, good});
    ImuReading nan = good;
    nan.stamp = Time::from_s(2);
    nan.q_W_V = Quat(bad, 0.0, 0.0, 0.0);
    ev.push_back({nan.stamp, Channel::kImu, 1, nan});
    REQUIRE(write_fixture(dir + "/imu.mcap", ev).ok());
    const auto back = read_fixture(dir + "/imu.mcap");
    INFO(back.error);
    REQUIRE_FALSE(back.error.empty());
    CHECK(back.error.find(dir + "/imu.mcap") != std::string::npos);
    CHECK(back.error.find("byte offset") != std::string::npos);
    CHECK(back.error.find("imu field 'orientation' is not finite") != std::string::npos);
  }
  // Ground truth too: it places the true-pose map's points.
  std::vector<Event> ev;
  TruthPose t;
  t.stamp = Time::from_s(1);
  t.p_W = Vec3(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0);
  ev.push_back({t.stamp, Channel::kTruthPose, 0, t});
  REQUIRE(write_fixture(dir + "/truth.mcap", ev).ok());
  const auto back = read_fixture(dir + "/truth.mcap");
  REQUIRE_FALSE(back.error.empty());
  CHECK(back.error.find("truth field 'position' is not finite") != std::string::npos);
}
