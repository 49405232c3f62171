#pragma once
// MCAP building blocks (spec: mcap.dev/spec): magic, opcodes, CRC-32 and a bounds-checked
// little-endian reader. Shared by the fixture writer, the reader and `orthosonar inspect`.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace orthosonar::replay::mcap {

inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr size_t kMagicSize = 8;
inline constexpr size_t kRecordPrefix = 9;  // opcode (1) + content length (8)

enum class Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};
inline constexpr uint8_t kMaxOpcode = 0x0F;

// Largest Attachment data the writer stores and the reader accepts.
inline constexpr uint64_t kMaxAttachmentBytes = uint64_t{1} << 30;

// The CRC-32 of zlib/PNG (polynomial 0xEDB88320), as MCAP specifies. `crc` is a previous
// result to continue from (0 to start).
uint32_t crc32(uint32_t crc, const uint8_t* data, size_t n);

// A cursor over a byte range. Every read checks bounds; after a failed read ok() is false
// and further reads return zeros, so parsers can read a record and check once.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : p_(data), n_(size) {}
  bool ok() const { return ok_; }
  size_t pos() const { return pos_; }
  size_t remaining() const { return ok_ ? n_ - pos_ : 0; }
  const uint8_t* here() const { return p_ + pos_; }

  uint8_t u8() { return static_cast<uint8_t>(le(1)); }
  uint16_t u16() { return static_cast<uint16_t>(le(2)); }
  uint32_t u32() { return static_cast<uint32_t>(le(4)); }
  uint64_t u64() { return le(8); }
  int16_t i16() { return static_cast<int16_t>(u16()); }
  double f64();
  // A uint32-length-prefixed string.
  std::string str();
  // Takes n raw bytes (nullptr on failure).
  const uint8_t* take(size_t n);
  bool skip(size_t n) { return take(n) != nullptr || n == 0; }

 private:
  uint64_t le(int n);
  const uint8_t* p_;
  size_t n_;
  size_t pos_ = 0;
  bool ok_ = true;
};

// Nominal schema names and encodings of our fixtures.
inline constexpr std::string_view kProfile = "ros1";
inline constexpr std::string_view kMessageEncoding = "ros1";
inline constexpr std::string_view kSchemaEncoding = "ros1msg";
inline constexpr std::string_view kMetadataName = "orthosonar";

}  // namespace orthosonar::replay::mcap
