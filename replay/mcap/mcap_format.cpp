#include "replay/mcap/mcap_format.hpp"

#include <bit>
#include <limits>

#include <zlib.h>

namespace orthosonar::replay::mcap {

uint32_t crc32(uint32_t crc, const uint8_t* data, size_t n) {
  // zlib's crc32 is the MCAP CRC; feed it in pieces that fit its uInt length.
  uLong c = crc;
  constexpr size_t kStep = size_t{1} << 30;
  while (n > 0) {
    const size_t k = n < kStep ? n : kStep;
    c = ::crc32(c, data, static_cast<uInt>(k));
    data += k;
    n -= k;
  }
  return static_cast<uint32_t>(c);
}

uint64_t ByteReader::le(int n) {
  const size_t k = static_cast<size_t>(n);
  if (!ok_ || n_ - pos_ < k) {
    ok_ = false;
    return 0;
  }
  uint64_t v = 0;
  for (size_t i = 0; i < k; ++i) v |= static_cast<uint64_t>(p_[pos_ + i]) << (8 * i);
  pos_ += k;
  return v;
}

double ByteReader::f64() { return std::bit_cast<double>(u64()); }

const uint8_t* ByteReader::take(size_t n) {
  if (!ok_ || n_ - pos_ < n) {
    ok_ = false;
    return nullptr;
  }
  const uint8_t* at = p_ + pos_;
  pos_ += n;
  return at;
}

std::string ByteReader::str() {
  const uint32_t len = u32();
  const uint8_t* at = take(len);
  if (at == nullptr) return {};
  return std::string(reinterpret_cast<const char*>(at), len);
}

}  // namespace orthosonar::replay::mcap
