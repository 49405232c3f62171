#pragma once
// Internal to the MCAP readers: the record layer both share (the fixture reader,
// replay/fixture/mcap_reader.cpp, and visit_messages, replay/mcap/mcap_generic.cpp): error locations,
// the record prefixes of the top level, Schema / Channel / Message / Chunk records, and a
// chunk's records (decompressed, with sizes checked before allocating, CRC-checked).
// Defined in mcap_chunks.cpp.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "replay/mcap/mcap_format.hpp"
#include "replay/mcap/mcap_generic.hpp"
#include "replay/mcap/mapped_file.hpp"

namespace orthosonar::replay::mcap {

// A Chunk record (or a run of messages outside chunks) located in the file.
struct ChunkRef {
  uint64_t offset = 0;          // of the Chunk record
  uint64_t records_offset = 0;  // of its (compressed) records
  uint64_t compressed_size = 0;
  uint64_t uncompressed_size = 0;
  uint32_t uncompressed_crc = 0;
  std::string compression;      // "" (none), "zstd" or "lz4" (LZ4 frame format)
  uint64_t start_ns = 0, end_ns = 0;
  // A run of Message records outside chunks (Layout::loose_runs), read like an
  // uncompressed chunk: offset = records_offset = its first record's file offset.
  bool loose = false;
  uint64_t message_count = 0;  // loose runs only
};

namespace detail {

inline constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;
inline constexpr uint64_t kReleaseBytes = uint64_t{8} << 20;  // scans release what they read in steps of this

std::string hex(uint64_t v);

// Where a record is: a file offset, or an offset inside a chunk's uncompressed records
// (chunk: the Chunk record's file offset, never 0 as the file starts with the magic).
struct Loc {
  uint64_t chunk = 0;
  uint64_t offset = 0;
};

Error at(const std::string& path, uint64_t offset, const std::string& what);
Error at(const std::string& path, Loc l, const std::string& what);

// RecoveryReport::detail of a file cut short at `pos`.
std::string cut_detail(const MappedFile& f, uint64_t pos, const std::string& why);

// The leading magic and the MCAP version.
Status check_magic(const MappedFile& f);
// The Footer record's offset when the file ends with one and the magic (0: it does not).
uint64_t trailing_footer(const MappedFile& f);
// After the Footer record, which ends at `end`: the magic, then the end of the file.
// Returns why the file is cut short ("" when it is not) or an error.
Result<std::string> check_trailing_magic(const MappedFile& f, uint64_t end);

// A record of the file's top level.
struct RecordHead {
  uint8_t op = 0;
  uint64_t len = 0;  // content bytes
  const uint8_t* body = nullptr;
  std::string cut;   // not empty: the file ends before the record does (why)
};
// Reads the prefix of the record at `pos`: an unsupported opcode and a first record that
// is not a Header are errors. A record running past the end of the file is a cut (a
// recording that died), unless the file ends with its footer (footer_pos != 0, see
// trailing_footer): then it, and a record running into the footer, is an error.
Result<RecordHead> record_head(const MappedFile& f, uint64_t pos, uint64_t footer_pos);

// Bytes read front to back: how far the data section goes, and releasing what was read
// every few MiB (MappedFile::release), so a long file is never resident as a whole.
class Progress {
 public:
  explicit Progress(const MappedFile& f) : f_(f) {}
  // Bytes up to `end` are read (in the data section: they count towards its CRC).
  void advance(uint64_t end, bool in_data_section);
  // A Data End record at `pos`: its CRC (0: not set) against the bytes before it.
  Status check_data_end(uint64_t pos, const uint8_t* body, uint64_t len) const;

 private:
  uint32_t data_crc() const;  // of [0, crc_end_)

  const MappedFile& f_;
  uint64_t crc_end_ = 0;   // the data section read so far: [0, crc_end_)
  uint64_t released_ = 0;  // [0, released_) released
};

bool read_map(ByteReader& r, std::map<std::string, std::string>& out);
// Record contents (after opcode and length). Errors name the path and `loc`.
Status parse_schema(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawSchema& out);
Status parse_channel(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawChannel& out);
// Fills the fields of the record (not chunk_offset, offset): data points into `body`.
Status parse_message(const std::string& path, Loc loc, const uint8_t* body, uint64_t len, RawMessage& out);
// A Chunk record at file offset `pos`: its fields (records stay in the file), checked
// for a supported compression, at most kMaxChunkBytes uncompressed, start <= end.
Status parse_chunk(const std::string& path, uint64_t pos, const uint8_t* body, uint64_t len, ChunkRef& out);

// The records of a chunk (or a run of loose messages): decompressed into `scratch` when
// compressed (sizes checked first), and CRC-checked (a CRC of 0 is not set).
Result<const uint8_t*> chunk_records(const MappedFile& file, const ChunkRef& c, std::vector<uint8_t>& scratch);

// One record inside a chunk's records.
struct InnerRecord {
  uint8_t op = 0;
  const uint8_t* body = nullptr;
  uint64_t len = 0;
};

// Splits a chunk's records; calls f(record, pos) for each, stopping at the first error.
template <class F>
Status for_each_record(const std::string& path, const ChunkRef& c, const uint8_t* records, F&& f) {
  uint64_t pos = 0;
  while (pos < c.uncompressed_size) {
    ByteReader r(records + pos, c.uncompressed_size - pos);
    const uint8_t op = r.u8();
    const uint64_t len = r.u64();
    if (!r.ok() || len > r.remaining()) return at(path, Loc{c.offset, pos}, "record runs past the end of the chunk");
    if (auto s = f(InnerRecord{op, r.here(), len}, pos); !s) return s;
    pos += kRecordPrefix + len;
  }
  return {};
}

}  // namespace detail
}  // namespace orthosonar::replay::mcap
