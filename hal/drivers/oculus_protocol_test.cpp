#include <catch2/catch.hpp>
#include <cmath>

#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/test_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;
using namespace orthosonar::hal::drivers::oculus;

TEST_CASE("real M1200d capture decodes with every header field checked", "[hal]") {
  const auto raw = testing::read_file(testing::testdata("oculus/m1200d_one_ping_8bit.raw"));
  REQUIRE(raw.size() == 182016);
  auto r = parse_ping_result(raw);
  INFO((r ? std::string("ok") : r.error().message));
  REQUIRE(r.ok());
  const PingResult& p = *r;
  // Header.
  CHECK(p.header.oculus_id == 0x4F53);
  CHECK(p.header.src_device_id == 7892);
  CHECK(p.header.dst_device_id == 0);
  CHECK(p.header.msg_id == kMsgSimplePingResult);
  CHECK(p.header.msg_version == 0);  // version 0 -> V1 layout
  CHECK(p.version == 1);
  CHECK(p.header.payload_size == 182000);
  // Fire message echoed by the device.
  CHECK(p.fire.master_mode == kModeHighFrequency);
  CHECK(p.fire.ping_rate == 0xC3);
  CHECK(p.fire.network_speed == 0x19);
  CHECK(p.fire.gamma == 127);
  CHECK(p.fire.flags == 0x19);
  CHECK((p.fire.flags & kFlagRangeAsMeters) != 0);
  CHECK((p.fire.flags & kFlagSimpleReturn) != 0);
  CHECK((p.fire.flags & kFlagGainAssist) != 0);
  CHECK((p.fire.flags & kFlagData16Bit) == 0);
  CHECK((p.fire.flags & kFlagSendGain) == 0);
  CHECK((p.fire.flags & kFlag512Beams) == 0);
  CHECK(p.fire.range == 2.0);
  CHECK(p.fire.gain_percent == 50.0);
  CHECK(p.fire.speed_of_sound_mps == Approx(1490.658551265436).epsilon(1e-12));
  CHECK(p.fire.salinity_ppt == 0.0);
  // Ping result.
  CHECK(p.ping_id == 415323);
  CHECK(p.status == 0);
  CHECK(p.frequency_hz == Approx(2098880.5970149254).epsilon(1e-12));
  CHECK(p.speed_of_sound_used_mps == Approx(1490.658551265436).epsilon(1e-12));
  CHECK(p.ping_start_time == 3103899264.0);
  CHECK(p.data_size == 0);
  CHECK(p.bytes_per_pixel() == 1);
  CHECK(p.range_resolution_m == Approx(0.0028421889710794315).epsilon(1e-12));
  CHECK(p.n_ranges == 703);
  CHECK(p.n_beams == 256);
  CHECK(p.image_offset == 2048);
  CHECK(p.image_size == 179968);
  CHECK(p.message_size == 182016);
  // Consistency.
  CHECK(p.image_offset + p.image_size <= p.message_size);
  CHECK(static_cast<uint32_t>(p.n_ranges) * p.n_beams * 1u == p.image_size);
  CHECK(p.range_resolution_m * p.n_ranges == Approx(p.fire.range).epsilon(0.002));
  REQUIRE(p.bearings_centideg.size() == 256);
  CHECK(p.bearings_centideg.front() == -3000);  // HF mode: 60 degree swath, +-30.00 degrees
  CHECK(p.bearings_centideg.back() == 3000);
  CHECK(p.bearings_centideg[127] == -11);
  CHECK(p.bearings_centideg[128] == 11);
  for (size_t i = 0; i + 1 < 256; ++i) CHECK(p.bearings_centideg[i] < p.bearings_centideg[i + 1]);
  for (size_t i = 0; i < 128; ++i) CHECK(p.bearings_centideg[i] == -p.bearings_centideg[255 - i]);
  REQUIRE(p.image.size() == 179968);
  CHECK(p.image[0] == raw[2048]);
  CHECK(p.image.back() == raw.back());

  auto s = to_sonar_ping(p, SonarMount::kVertical, kPartM1200d, Time::from_ms(5));
  REQUIRE(s.ok());
  CHECK(s->rows == 703);
  CHECK(s->cols == 256);
  CHECK(s->part_number == kPartM1200d);
  CHECK(s->ping_id == 415323);
  CHECK(s->bearings_rad.front() == Approx(-30.0 * M_PI / 180.0));
  CHECK(s->bearings_rad.back() == Approx(30.0 * M_PI / 180.0));
  CHECK(s->max_range_m() == Approx(1.998).epsilon(0.001));
  // REP-103 mirror: SonarPing column c is the device's beam 255 - c, bearing negated.
  CHECK(s->at(0, 0) == p.image[255]);
  CHECK(s->at(0, 255) == p.image[0]);
  CHECK(s->at(702, 10) == p.image[702u * 256u + 245u]);
  CHECK(s->bearings_rad[3] == Approx(-p.bearings_centideg[252] / 100.0 * M_PI / 180.0));
}

TEST_CASE("truncated real capture is an error at every cut", "[hal]") {
  const auto raw = testing::read_file(testing::testdata("oculus/m1200d_one_ping_8bit.raw"));
  REQUIRE(raw.size() == 182016);
  for (size_t cut : {0ul, 1ul, 15ul, 16ul, 100ul, 121ul, 122ul, 700ul, 2048ul, 182015ul}) {
    auto r = parse_ping_result(std::span<const uint8_t>(raw.data(), cut));
    CHECK_FALSE(r.ok());
  }
}

TEST_CASE("ping results round-trip in V1 and V2 with gain and 16-bit data", "[hal]") {
  for (int version : {1, 2}) {
    for (uint8_t bpp : {uint8_t{1}, uint8_t{2}}) {
      for (bool gain : {false, true}) {
        const SonarPing s = testing::small_ping(SonarMount::kHorizontal, 7, Time::from_ms(1), 20, 16, bpp);
        PingResult p = ping_result_from(s, version, 33);
        if (gain) {
          p.fire.flags |= kFlagSendGain;
          for (uint16_t i = 0; i < p.n_ranges; ++i) p.row_gains.push_back(1000u + i);
        }
        const Bytes wire = encode_ping_result(p);
        CHECK(wire.size() == (version == 2 ? kPingV2Size : kPingV1Size) + 2u * 16 + 20u * (16u * bpp + (gain ? 4u : 0u)));
        auto back = parse_ping_result(wire);
        REQUIRE(back.ok());
        CHECK(back->version == version);
        CHECK(back->row_gains == p.row_gains);
        CHECK(back->image == p.image);  // wire order (mirrored w.r.t. SonarPing)
        CHECK(back->image != s.image);
        auto s2 = to_sonar_ping(*back, SonarMount::kHorizontal, kPartM750d, s.stamp);
        REQUIRE(s2.ok());
        CHECK(s2->image == s.image);
        CHECK(s2->bytes_per_pixel == bpp);
        for (size_t i = 0; i < s.bearings_rad.size(); ++i) CHECK(s2->bearings_rad[i] == Approx(s.bearings_rad[i]).margin(1e-9));
      }
    }
  }
}

TEST_CASE("fire messages V1 and V2 encode and decode", "[hal]") {
  FireConfig c;
  c.range = 12.5;
  c.gain_percent = 40;
  c.gamma = 200;
  c.flags = kFlagRangeAsMeters | kFlagData16Bit | kFlag512Beams;
  c.ext_flags = 0;
  for (int version : {1, 2}) {
    const Bytes b = encode_fire(c, version, 0, 7);
    CHECK(b.size() == (version == 2 ? kFireV2Size : kFireV1Size));
    auto m = parse_message(b);
    REQUIRE(m.ok());
    const auto* f = std::get_if<FireMessage>(&*m);
    REQUIRE(f != nullptr);
    CHECK(f->config == c);
    CHECK(f->header.dst_device_id == 7);
  }
}

TEST_CASE("stream parser resynchronises on the id after garbage and split reads", "[hal]") {
  const auto raw = testing::read_file(testing::testdata("oculus/m1200d_one_ping_8bit.raw"));
  REQUIRE(raw.size() == 182016);
  StatusMessage st;
  st.part_number = kPartM1200d;
  st.device_id = 7892;
  Bytes stream = {0x00, 0x53, 0x53, 0x4F, 0x01, 0xFF, 0x12};  // garbage with a false id
  const Bytes status = encode_status(st);
  stream.insert(stream.end(), raw.begin(), raw.end());
  stream.insert(stream.end(), {0x4F, 0x53, 0x99});
  stream.insert(stream.end(), status.begin(), status.end());
  stream.insert(stream.end(), raw.begin(), raw.begin() + 500);  // truncated tail
  StreamParser parser;
  std::vector<Message> got;
  for (size_t i = 0; i < stream.size(); i += 997) {
    parser.push(std::span<const uint8_t>(stream.data() + i, std::min<size_t>(997, stream.size() - i)));
    while (auto m = parser.pop()) got.push_back(std::move(*m));
  }
  REQUIRE(got.size() == 2);
  REQUIRE(std::holds_alternative<PingResult>(got[0]));
  CHECK(std::get<PingResult>(got[0]).ping_id == 415323);
  REQUIRE(std::holds_alternative<StatusMessage>(got[1]));
  CHECK(std::get<StatusMessage>(got[1]).part_number == kPartM1200d);
  CHECK(parser.stats().messages == 2);
  CHECK(parser.stats().malformed >= 1);  // the false id at offset 1
  CHECK(parser.stats().garbage_bytes >= 4);
  CHECK(parser.buffered() == 500);
}

TEST_CASE("inconsistent ping sizes are rejected", "[hal]") {
  const SonarPing s = testing::small_ping(SonarMount::kVertical, 1, Time::from_ms(1), 10, 8);
  Bytes wire = encode_ping_result(ping_result_from(s, 1, 2));
  auto bad = wire;
  bad[kPingV1Size - 12] ^= 0x01;  // imageOffset
  CHECK_FALSE(parse_ping_result(bad).ok());
  bad = wire;
  bad[kPingV1Size - 16] = 9;  // nBeams low byte: 9 beams no longer matches imageSize
  CHECK_FALSE(parse_ping_result(bad).ok());
  bad = wire;
  bad[0] = 0x00;  // id
  CHECK_FALSE(parse_ping_result(bad).ok());
  CHECK(parse_ping_result(wire).ok());
}
