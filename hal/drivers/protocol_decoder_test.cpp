// Raw-capture decoding for `orthosonar inspect --protocol`: offsets, counts, chunking.
#include "hal/drivers/protocol_decoder.hpp"

#include <catch2/catch.hpp>
#include <algorithm>

#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/test_support.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace {

std::vector<uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

std::string without_line_end(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

struct Decoded {
  std::vector<DecodedMessage> messages;
  DecodeCounts counts;
};

Decoded decode_all(Protocol p, const std::vector<uint8_t>& bytes, size_t step) {
  auto d = make_decoder(p);
  Decoded out;
  for (size_t at = 0; at < bytes.size(); at += step) {
    d->push(std::span<const uint8_t>(bytes).subspan(at, std::min(step, bytes.size() - at)));
    while (auto m = d->pop()) out.messages.push_back(*m);
  }
  d->finish();
  while (auto m = d->pop()) out.messages.push_back(*m);
  out.counts = d->counts();
  return out;
}

}  // namespace

TEST_CASE("protocol names round-trip and an unknown one is an error listing them", "[hal]") {
  for (auto p : {Protocol::kOculus, Protocol::kVn100, Protocol::kA50, Protocol::kPrti, Protocol::kDepth})
    CHECK(*protocol_from_name(protocol_name(p)) == p);
  auto bad = protocol_from_name("nmea");
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().message.find("vn100") != std::string::npos);
}

TEST_CASE("the real VN-100 log decodes to 99 packets at their byte offsets, in any read size", "[hal]") {
  const auto log = testing::read_file(testing::testdata("vn100/F00294"));
  const auto whole = decode_all(Protocol::kVn100, log, log.size());
  REQUIRE(whole.messages.size() == 99);
  CHECK(whole.counts.good == 99);
  CHECK(whole.counts.bad == 0);
  CHECK(whole.counts.unsupported == 0);
  CHECK(whole.counts.trailing_bytes == 0);
  uint64_t in_packets = 0;
  for (const auto& m : whole.messages) {
    // Each reported offset holds the packet's header, and its size is the packet's length.
    REQUIRE(m.offset + m.size <= log.size());
    CHECK(log[m.offset] == vn100::kSync);
    CHECK(log[m.offset + 1] == 0x14);
    CHECK(m.size == 124);
    auto p = vn100::parse_packet(std::span<const uint8_t>(log).subspan(m.offset, m.size));
    CHECK(p.ok());
    in_packets += m.size;
  }
  CHECK(whole.counts.skipped_bytes == log.size() - in_packets);
  for (size_t step : {1u, 7u, 500u}) {
    const auto chunked = decode_all(Protocol::kVn100, log, step);
    REQUIRE(chunked.messages.size() == whole.messages.size());
    for (size_t i = 0; i < chunked.messages.size(); ++i) {
      CHECK(chunked.messages[i].offset == whole.messages[i].offset);
      CHECK(chunked.messages[i].fields == whole.messages[i].fields);
    }
    CHECK(chunked.counts.skipped_bytes == whole.counts.skipped_bytes);
  }
}

TEST_CASE("a VN-100 capture cut inside a packet reports the rest as trailing bytes", "[hal]") {
  auto log = testing::read_file(testing::testdata("vn100/F00294"));
  const auto whole = decode_all(Protocol::kVn100, log, log.size());
  log.resize(whole.messages.back().offset + 50);
  const auto cut = decode_all(Protocol::kVn100, log, 4096);
  CHECK(cut.counts.good == 98);
  CHECK(cut.counts.trailing_bytes == 50);
}

TEST_CASE("the Oculus capture decodes its ping at offset 0", "[hal]") {
  const auto raw = testing::read_file(testing::testdata("oculus/m1200d_one_ping_8bit.raw"));
  const auto d = decode_all(Protocol::kOculus, raw, 65536);
  REQUIRE(d.counts.good >= 1);
  REQUIRE_FALSE(d.messages.empty());
  CHECK(d.messages[0].offset == 0);
  CHECK(d.messages[0].type == "ping");
  CHECK(d.counts.bad == 0);
}

TEST_CASE("A50 lines: offsets, duplicates counted, responses listed as other, bad lines named", "[hal]") {
  dvl::DvlVelocity v;
  v.velocity_D_mps = Vec3(0.1, -0.2, 0.05);
  v.valid = true;
  v.altitude_m = 3.5;
  const std::string l1 = without_line_end(dvl::encode_a50_velocity(v, 100.0, 1000));
  const std::string l2 = without_line_end(dvl::encode_a50_velocity(v, 100.0, 2000));
  const std::string resp = R"({"response_to":"get_config","success":true,"error_message":"","result":{},"format":"json_v3.1","type":"response"})";
  const std::string text = l1 + "\r\n" + l1 + "\n\n" + resp + "\n" + "{not json\n" + l2;  // last line: no line end
  const auto d = decode_all(Protocol::kA50, bytes_of(text), 5);
  REQUIRE(d.messages.size() == 3);
  CHECK(d.messages[0].offset == 0);
  CHECK(d.messages[0].size == l1.size());
  CHECK(d.messages[0].type == "velocity");
  CHECK(d.messages[1].type == "other");
  CHECK(d.messages[1].offset == text.find(resp));
  CHECK(d.messages[2].offset == text.rfind(l2));
  CHECK(d.counts.good == 2);
  CHECK(d.counts.duplicates == 1);
  CHECK(d.counts.other == 1);
  CHECK(d.counts.bad == 1);
  CHECK(d.counts.last_error.find("byte " + std::to_string(text.find("{not"))) == 0);
}

TEST_CASE("PRTI lines: other sentences counted, PRTI03 unsupported, bad checksum rejected", "[hal]") {
  const std::string good = "$PRTI01,1000,8,1464,-1205,-24,-347,79380,300,-200,400,100,0000*21";
  const std::string earth = "$PRTI02,1000,8,1464,-1205,-24,-347,79380,300,-200,400,100,0000*22";
  const std::string bad = "$PRTI01,1000,8,1464,-1205,-24,-347,79380,300,-200,400,100,0000*22";
  const std::string text = "$GPGGA,1*00\r\n" + good + "\r\n" + earth + "\r\n" + bad + "\r\n$PRTI03,1,2*00\r\n";
  const auto d = decode_all(Protocol::kPrti, bytes_of(text), 3);
  REQUIRE(d.messages.size() == 2);
  CHECK(d.messages[0].type == "PRTI01");
  CHECK(d.messages[0].offset == text.find(good));
  CHECK(d.messages[1].type == "PRTI02");
  CHECK(d.counts.good == 2);
  CHECK(d.counts.other == 1);
  CHECK(d.counts.bad == 1);
  CHECK(d.counts.unsupported == 1);
}

TEST_CASE("an over-long line is rejected without buffering it", "[hal]") {
  std::string text(DecoderLimits::kMaxLine + 10, 'x');
  text += "\n" + without_line_end(dvl::encode_depth_line(4.25)) + "\n";
  const auto d = decode_all(Protocol::kDepth, bytes_of(text), 4096);
  REQUIRE(d.messages.size() == 1);
  CHECK(d.messages[0].type == "DEPTH");
  CHECK(d.messages[0].offset == DecoderLimits::kMaxLine + 11);
  CHECK(d.counts.bad == 1);
  CHECK(d.counts.skipped_bytes == DecoderLimits::kMaxLine + 10);
}
