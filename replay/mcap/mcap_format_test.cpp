// The MCAP CRC (mcap_format.cpp's crc32, libdeflate's CRC-32) against the standard's check
// value and against zlib's crc32 on random data, whole and fed in pieces.
#include "replay/mcap/mcap_format.hpp"

#include <zlib.h>

#include <catch2/catch.hpp>
#include <rapidcheck.h>
#include <rapidcheck/catch.h>
#include <string>
#include <vector>

namespace mcap = orthosonar::replay::mcap;

namespace {

uint32_t zlib_crc(const std::vector<uint8_t>& d) {
  return static_cast<uint32_t>(::crc32(0, d.data(), static_cast<uInt>(d.size())));
}

}  // namespace

TEST_CASE("MCAP CRC-32 is the ISO-HDLC CRC (check value, empty input)", "[mcap][crc]") {
  const std::string check = "123456789";
  CHECK(mcap::crc32(0, reinterpret_cast<const uint8_t*>(check.data()), check.size()) == 0xCBF43926u);
  CHECK(mcap::crc32(0, nullptr, 0) == 0u);
  CHECK(mcap::crc32(0x12345678u, nullptr, 0) == 0x12345678u);
  // 1 MiB of a counter pattern: the folding path, not only the tail loop.
  std::vector<uint8_t> big(1u << 20);
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<uint8_t>(i * 131u + (i >> 9));
  CHECK(mcap::crc32(0, big.data(), big.size()) == zlib_crc(big));
}

TEST_CASE("MCAP CRC-32 equals zlib's on random data, whole and in pieces", "[mcap][crc][rapidcheck]") {
  rc::prop("mcap::crc32(whole) == zlib == crc32 continued over a split", [] {
    const auto data = *rc::gen::container<std::vector<uint8_t>>(*rc::gen::inRange<size_t>(0, 5000),
                                                                 rc::gen::arbitrary<uint8_t>());
    const size_t cut = *rc::gen::inRange<size_t>(0, data.size() + 1);
    const uint32_t whole = mcap::crc32(0, data.data(), data.size());
    RC_ASSERT(whole == zlib_crc(data));
    const uint32_t first = mcap::crc32(0, data.data(), cut);
    RC_ASSERT(mcap::crc32(first, data.data() + cut, data.size() - cut) == whole);
  });
}
