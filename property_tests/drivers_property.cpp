// Random-corruption properties of the device parsers (Oculus, VN-100, A50, PRTI01, depth):
// whatever bytes arrive, a parser returns a valid message or an error, never crashes or reads
// out of bounds (this suite also runs under the asan preset). RC_PARAMS="seed=..." replays.
#include <rapidcheck/catch.h>

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace {

// Applies 1..8 random byte edits (flip, overwrite, insert, delete, truncate) to a valid message.
Bytes corrupt(Bytes b) {
  const int edits = *rc::gen::inRange(1, 9);
  for (int e = 0; e < edits && !b.empty(); ++e) {
    const size_t at = static_cast<size_t>(*rc::gen::inRange<size_t>(0, b.size()));
    switch (*rc::gen::inRange(0, 5)) {
      case 0: b[at] = static_cast<uint8_t>(b[at] ^ (1u << *rc::gen::inRange(0, 8))); break;
      case 1: b[at] = *rc::gen::arbitrary<uint8_t>(); break;
      case 2: b.insert(b.begin() + static_cast<std::ptrdiff_t>(at), *rc::gen::arbitrary<uint8_t>()); break;
      case 3: b.erase(b.begin() + static_cast<std::ptrdiff_t>(at)); break;
      default: b.resize(at); break;
    }
  }
  return b;
}

std::string corrupt_text(const std::string& s) {
  const Bytes b = corrupt(Bytes(s.begin(), s.end()));
  return std::string(b.begin(), b.end());
}

SonarPing any_ping() {
  SonarPing s;
  s.rows = *rc::gen::inRange<uint16_t>(1, 12);
  s.cols = *rc::gen::inRange<uint16_t>(1, 10);
  s.bytes_per_pixel = *rc::gen::element<uint8_t>(1, 2);
  s.range_resolution_m = 0.05;
  for (uint16_t c = 0; c < s.cols; ++c) s.bearings_rad.push_back(-1.0 + 0.1 * c);
  s.image = *rc::gen::container<std::vector<uint8_t>>(static_cast<size_t>(s.rows) * s.cols * s.bytes_per_pixel,
                                                      rc::gen::arbitrary<uint8_t>());
  return s;
}

}  // namespace

TEST_CASE("oculus parser survives random corruption", "[property]") {
  rc::prop("corrupted ping results parse or fail cleanly", [] {
    oculus::PingResult p = oculus::ping_result_from(any_ping(), *rc::gen::element(1, 2), 3);
    if (*rc::gen::arbitrary<bool>()) {
      p.fire.flags |= oculus::kFlagSendGain;
      p.row_gains.assign(p.n_ranges, 7u);
    }
    const Bytes bad = corrupt(oculus::encode_ping_result(p));
    auto r = oculus::parse_message(bad);
    if (r) {
      if (const auto* q = std::get_if<oculus::PingResult>(&*r)) {
        RC_ASSERT(q->bearings_centideg.size() == q->n_beams);
        RC_ASSERT(q->image.size() == static_cast<size_t>(q->n_ranges) * q->n_beams * static_cast<size_t>(q->bytes_per_pixel()));
        RC_ASSERT(static_cast<uint64_t>(q->image_offset) + q->image_size <= bad.size());
      }
    } else {
      RC_ASSERT(!r.error().message.empty());
    }
    // The stream parser on the same bytes in random chunk sizes never returns a bad ping.
    oculus::StreamParser sp;
    size_t i = 0;
    while (i < bad.size()) {
      const size_t n = std::min(bad.size() - i, *rc::gen::inRange<size_t>(1, 300));
      sp.push(std::span<const uint8_t>(bad.data() + i, n));
      i += n;
      while (auto m = sp.pop())
        if (const auto* q = std::get_if<oculus::PingResult>(&*m)) RC_ASSERT(q->bearings_centideg.size() == q->n_beams);
    }
  });
}

TEST_CASE("oculus stream parser survives arbitrary bytes", "[property]") {
  rc::prop("random bytes with embedded ids", [] {
    auto bytes = *rc::gen::container<std::vector<uint8_t>>(rc::gen::arbitrary<uint8_t>());
    const size_t ids = *rc::gen::inRange<size_t>(0, 4);
    for (size_t k = 0; k < ids && bytes.size() >= 2; ++k) {
      const size_t at = *rc::gen::inRange<size_t>(0, bytes.size() - 1);
      bytes[at] = 0x53;
      bytes[at + 1] = 0x4F;
    }
    oculus::StreamParser sp;
    sp.push(bytes);
    while (sp.pop()) {
    }
    RC_ASSERT(sp.buffered() <= bytes.size());
  });
}

TEST_CASE("vn100 parser survives random corruption", "[property]") {
  rc::prop("corrupted packets parse or fail cleanly", [] {
    vn100::Message m;
    m.time_startup_ns = *rc::gen::arbitrary<uint64_t>();
    if (*rc::gen::arbitrary<bool>()) m.quat_xyzw = std::array<float, 4>{0.f, 0.f, 0.6f, 0.8f};
    else m.ypr_deg = std::array<float, 3>{10.f, 2.f, -3.f};
    if (*rc::gen::arbitrary<bool>()) m.angular_rate = std::array<float, 3>{0.1f, 0.2f, 0.3f};
    if (*rc::gen::arbitrary<bool>()) m.accel = std::array<float, 3>{0.f, 0.f, -9.8f};
    const Bytes bad = corrupt(vn100::encode_packet(m));
    auto r = vn100::parse_packet(bad);
    if (r) (void)vn100::to_imu_reading(*r, Quat::Identity(), Time());
    vn100::StreamParser sp;
    sp.push(bad);
    while (auto q = sp.pop()) (void)vn100::to_imu_reading(*q, Quat::Identity(), Time());
    RC_ASSERT(sp.messages() <= 1 + bad.size() / 6);
  });
}

TEST_CASE("a50 parser survives random corruption", "[property]") {
  rc::prop("corrupted JSON lines parse or fail cleanly", [] {
    dvl::DvlVelocity v;
    v.valid = *rc::gen::arbitrary<bool>();
    v.velocity_D_mps = Vec3(0.25, -0.125, 0.5);
    v.altitude_m = 2.5;
    const std::string bad = corrupt_text(dvl::encode_a50_velocity(v, 100.0));
    auto r = dvl::parse_a50_line(bad);
    if (r && r->has_value()) RC_ASSERT((*r)->velocity_D_mps.allFinite());
    LineFramer f(64);
    f.push(as_bytes(bad));
    while (auto line = f.pop()) (void)dvl::parse_a50_line(*line);
  });
}

TEST_CASE("prti01 and depth parsers survive random corruption", "[property]") {
  rc::prop("corrupted sentences parse or fail cleanly", [] {
    dvl::DvlVelocity v;
    v.valid = *rc::gen::arbitrary<bool>();
    v.velocity_D_mps = Vec3(0.3, -0.02, 0.01);
    v.altitude_m = 4.0;
    const std::string bad = corrupt_text(dvl::encode_prti01(v, *rc::gen::arbitrary<uint32_t>(), 12345));
    auto r = dvl::parse_prti01(bad);
    if (r) RC_ASSERT(r->velocity_D_mps.allFinite());
    auto d = dvl::parse_depth_line(corrupt_text(dvl::encode_depth_line(3.5)));
    if (d) RC_ASSERT(std::isfinite(*d));
  });
}
