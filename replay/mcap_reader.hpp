#pragma once
// Reading MCAP fixtures, ours and other writers' (docs/ARCHITECTURE.md, "MCAP files the
// reader accepts"): a memory-mapped file, a structural scan of its records (checking
// magic, opcodes, the data section CRC and the summary CRC, and recovering the readable
// prefix of a truncated file), and decoding one chunk into events.
// Errors name the file and the byte offset at fault.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"
#include "replay/fixture.hpp"

namespace orthosonar::replay::mcap {

// A read-only memory map of a whole file (empty files map to nothing).
class MappedFile {
 public:
  static Result<std::unique_ptr<MappedFile>> open(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const uint8_t* data() const { return data_; }
  size_t size() const { return size_; }
  const std::string& path() const { return path_; }
  // Drops the pages of [offset, offset + n) (widened to whole pages) from this process's
  // resident set; the bytes stay readable (a later read faults them back in from the page
  // cache). The scan and read_chunk release what they have consumed, so replaying a
  // recording keeps only the chunks in use resident, not the file (issue 16).
  void release(uint64_t offset, uint64_t n) const;

 private:
  MappedFile() = default;
  const uint8_t* data_ = nullptr;
  size_t size_ = 0;
  std::string path_;
};

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

struct ChannelRef {
  uint16_t id = 0;
  Channel channel = Channel::kImu;
  std::string topic;
  std::string schema_name;
};

// A decoded message with where it came from (for error messages).
struct LocatedEvent {
  Event event;
  uint64_t chunk_offset = 0;  // file offset of its chunk (0: not in a chunk)
  uint64_t offset = 0;        // file offset, or offset inside the uncompressed chunk
};
std::string describe_location(const LocatedEvent& e);

struct Statistics {
  uint64_t message_count = 0;
  uint32_t chunk_count = 0;
  uint64_t start_ns = 0, end_ns = 0;
  std::map<uint16_t, uint64_t> channel_counts;
};

// How a file was read (`orthosonar inspect` prints it).
struct ReadInfo {
  bool summary_present = false;      // the footer points at a summary section
  // No usable summary (none, a truncated file, or one without a Statistics record that
  // lists every channel): every chunk was decompressed once at open, front to back, to
  // find the Schema and Channel records inside it and to count the messages.
  bool read_by_linear_scan = false;
  std::string summary_note;          // why a present summary was not used ("" otherwise)
  uint64_t chunk_count = 0;
  uint64_t loose_message_count = 0;  // Message records outside chunks
  std::vector<std::string> compressions;  // distinct chunk compressions, in file order ("" = none)
  bool message_indexes = false;      // Message Index records after chunks (the reader does not need them)
  bool chunk_indexes = false;        // Chunk Index records in the summary (nor these)
  uint64_t truncated_bytes = 0;      // bytes after the last complete record (0: a complete file)
};

struct Layout {
  std::string profile, library;
  FixtureMetadata metadata;
  std::map<uint16_t, ChannelRef> channels;
  std::vector<ChunkRef> chunks;              // in file order
  // Message records outside chunks, in runs of consecutive records (each at most one
  // second of log time and 8 MiB): the scan checks their headers and channels only; the
  // messages are decoded lazily, run by run, like chunks (read_chunk).
  std::vector<ChunkRef> loose_runs;
  uint64_t loose_message_count = 0;
  std::vector<Attachment> attachments;       // Attachment records (CRC-checked), file order
  std::optional<Statistics> statistics;      // from the summary, when present
  uint64_t message_count = 0;  // from the summary's Statistics, or counted by the linear scan
  RecoveryReport recovery;     // messages_recovered = message_count
  ReadInfo read;
};

// Scans the record structure. Schema and Channel records are taken from the data section
// (outside and, on a linear scan, inside chunks) and from the summary. The summary is
// used when it is complete (a Statistics record whose channels all have Channel records);
// otherwise the file is read by a linear scan (ReadInfo), decompressing and CRC-checking
// each chunk once, in file order, one at a time (memory: one chunk). A truncated file (no
// footer, or a record running past the end of a file that does not end with its footer)
// is not an error: the layout covers the complete records and `recovery` says how much
// was kept (a warning for the caller to show).
Result<Layout> scan(const MappedFile& file);

// Decompresses a chunk (or reads a run of loose messages), checks its CRC, and appends
// its messages (decoded) to `out`, then releases the chunk's file bytes
// (MappedFile::release). `scratch` is reused between calls.
Status read_chunk(const MappedFile& file, const Layout& layout, const ChunkRef& chunk,
                  std::vector<LocatedEvent>& out, std::vector<uint8_t>& scratch);

// The FixtureSource over a scanned file (FixtureSource::open is MappedFile::open, scan and
// this; summarize_fixture uses the layout too). Defined in fixture_source.cpp.
std::unique_ptr<FixtureSource> make_source(std::unique_ptr<MappedFile> file, Layout layout);

}  // namespace orthosonar::replay::mcap
