#pragma once
// MCAP for any topics, schemas and encodings (mcap.dev/spec), beside the fixture-specific
// layer (replay/fixture/fixture.hpp): a writer of schemas, channels and messages (used by the
// fixture writer itself, by `orthosonar export --to ros2-mcap` and by a run's
// results.mcap), and a reader that visits every message of another writer's file (ROS 2
// recordings with `cdr` messages, `ros1` recordings of any topic) for `orthosonar import`.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "replay/mcap/attachment.hpp"
#include "replay/mcap/recovery.hpp"

namespace orthosonar::replay::mcap {

struct GenericWriterOptions {
  std::string profile;                          // Header.profile, e.g. "ros1", "ros2", ""
  std::string library;                          // Header.library, e.g. "orthosonar 0.9"
  std::string compression = "zstd";             // chunk compression: "zstd" or "" (none)
  int zstd_level = 3;
  int64_t chunk_max_log_ns = 1'000'000'000;     // close a chunk at least every second of log time
  uint64_t chunk_max_bytes = 8u << 20;          // ... or when this large
  // The first id add_channel returns (then +1 per channel). Our fixtures' channel ids are
  // their Channel values, from 0; other files' from 1, as most writers do.
  uint16_t first_channel_id = 1;
};

// An append-only indexed MCAP writer: Header, then (as they are first used) Schema and
// Channel records in the data section, chunks each followed by their Message Index
// records, Data End, and a summary (schemas, channels, Statistics, Chunk Index, Metadata
// and Attachment Index records, Summary Offsets) and Footer with its CRC. Every chunk is
// written and flushed when it closes. Bytes are a pure function of the calls.
// Errors name the path; an I/O failure is sticky.
class GenericWriter {
 public:
  static Result<std::unique_ptr<GenericWriter>> open(const std::string& path, const GenericWriterOptions& options);
  virtual ~GenericWriter() = default;
  // Schema ids start at 1, channel ids at options.first_channel_id; the records are written
  // (in the data section, outside chunks) when the first message uses them. An id past
  // 65535 is 0 and a sticky error.
  virtual uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data) = 0;
  virtual uint16_t add_channel(uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                               const std::map<std::string, std::string>& metadata = {}) = 0;
  virtual Status write(uint16_t channel_id, uint32_t sequence, uint64_t log_time_ns, uint64_t publish_time_ns,
                       const uint8_t* data, size_t size) = 0;
  // A Metadata record (written now, outside chunks, indexed in the summary).
  virtual Status metadata(const std::string& name, const std::map<std::string, std::string>& values) = 0;
  // An Attachment record (written now, outside chunks, with its CRC; indexed in the summary).
  virtual Status attach(const Attachment& attachment) = 0;
  virtual Status close() = 0;
};

// What a reader of another writer's file sees.
struct RawSchema {
  uint16_t id = 0;
  std::string name, encoding;   // e.g. "sensor_msgs/msg/Imu", "ros2msg"
  std::string data;             // the definition text
};
struct RawChannel {
  uint16_t id = 0;
  uint16_t schema_id = 0;       // 0: no schema
  std::string topic, message_encoding;  // e.g. "/imu", "cdr"
  std::map<std::string, std::string> metadata;
};
struct RawMessage {             // valid only during the callback
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0, publish_time_ns = 0;
  const uint8_t* data = nullptr;
  size_t size = 0;
  uint64_t chunk_offset = 0;    // file offset of its chunk (0: outside chunks)
  uint64_t offset = 0;          // offset of its record (inside the uncompressed chunk, or in the file)
};

// Visits a whole MCAP file front to back (chunks "", "zstd", "lz4", checked against
// their CRCs; messages inside and outside chunks): `on_channel` once per channel (with
// its schema, or nullptr) before the first message on it, `on_message` for every message
// in file order. Summary, indexes and attachments are not needed. A file cut short is
// read up to its last complete record and `recovery` (when given) says so; corrupt data
// is an error naming the file and byte offset. The file is memory-mapped and released as
// it is consumed (memory: one chunk).
Status visit_messages(const std::string& path,
                      const std::function<Status(const RawChannel&, const RawSchema*)>& on_channel,
                      const std::function<Status(const RawMessage&)>& on_message,
                      RecoveryReport* recovery = nullptr);

}  // namespace orthosonar::replay::mcap
