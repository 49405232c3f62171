#include "core/canonical.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

using orthosonar::CanonicalWriter;

TEST_CASE("canonical integers are little-endian whatever the host", "[unit]") {
  CanonicalWriter w;
  w.put_u16(0x0102);
  w.put_u32(0x03040506u);
  w.put_u64(0x0708090a0b0c0d0eull);
  w.put_i64(-2);
  const std::vector<uint8_t> expect = {0x02, 0x01, 0x06, 0x05, 0x04, 0x03, 0x0e, 0x0d, 0x0c, 0x0b,
                                       0x0a, 0x09, 0x08, 0x07, 0xfe, 0xff, 0xff, 0xff, 0xff, 0xff,
                                       0xff, 0xff};
  CHECK(w.bytes() == expect);
}

TEST_CASE("canonical floats keep their bit pattern", "[unit]") {
  CanonicalWriter a, b;
  a.put_f64(0.0);
  b.put_f64(-0.0);
  CHECK(a.bytes() != b.bytes());  // equal as numbers, different bytes: digests must see it
  CanonicalWriter w;
  w.put_f64(1.0);
  CHECK(w.bytes() == std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0xf0, 0x3f});
  CanonicalWriter f;
  f.put_f32(1.0f);
  CHECK(f.bytes() == std::vector<uint8_t>{0, 0, 0x80, 0x3f});
}

TEST_CASE("canonical strings points and poses have fixed layouts", "[unit]") {
  CanonicalWriter w;
  w.put_string("ab");
  CHECK(w.bytes() == std::vector<uint8_t>{2, 0, 0, 0, 'a', 'b'});
  CanonicalWriter p;
  p.put_points({Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(4, 5, 6)});
  CHECK(p.size() == 8 + 2 * 12);
  CanonicalWriter s;
  orthosonar::SE3 T = orthosonar::SE3::Identity();
  T.translation() = orthosonar::Vec3(1, 2, 3);
  s.put_se3(T);
  REQUIRE(s.size() == 96);
  // Row 0 ends with x = 1.0: bytes 24..31.
  CHECK(std::vector<uint8_t>(s.bytes().begin() + 24, s.bytes().begin() + 32) ==
        std::vector<uint8_t>{0, 0, 0, 0, 0, 0, 0xf0, 0x3f});
}

TEST_CASE("canonical patch overwrites a length field", "[unit]") {
  CanonicalWriter w;
  w.put_u32(0);
  w.put_u8(9);
  w.patch_u32(0, 0xa1b2c3d4u);
  CHECK(w.bytes() == std::vector<uint8_t>{0xd4, 0xc3, 0xb2, 0xa1, 9});
}
