#pragma once
// Fixtures: recordings of event streams as MCAP files (SPEC §11). The writer appends
// events in the order the core consumed them; the source replays them in
// (stamp, channel, sequence) order.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/event_source.hpp"

namespace orthosonar::replay {

// Free-form metadata written as an MCAP metadata record named "orthosonar":
// scene, seed, extrinsics, software version, ... Ordered map: deterministic bytes.
using FixtureMetadata = std::map<std::string, std::string>;

struct WriterOptions {
  bool compress = true;                          // zstd chunks
  int64_t chunk_max_stream_ns = 1'000'000'000;   // close a chunk at least every second of stream time
  uint64_t chunk_max_bytes = 8u << 20;           // ... or when this large
  int zstd_level = 3;                            // libzstd compression level
};

class FixtureWriter {
 public:
  static Result<std::unique_ptr<FixtureWriter>> open(const std::string& path,
                                                     const FixtureMetadata& metadata,
                                                     const WriterOptions& options = {});
  virtual ~FixtureWriter() = default;
  // Appends one event (messages are ros1msg, schemas in replay/ros1_codec.hpp; MCAP log
  // time = event.stamp, MCAP sequence = event.sequence). Errors name the path. An event
  // that cannot be stored exactly (negative stamp, stamp beyond the ros1 time range,
  // sequence > uint32, payload not of the event's channel, image/bearing/label sizes that
  // disagree with rows and cols) is rejected and nothing is written; an I/O failure is
  // sticky. A chunk is written and flushed as soon as it closes (see WriterOptions), so a
  // killed process leaves a file readable up to its last complete chunk.
  virtual Status write(const Event& event) = 0;
  // Writes the summary section and footer. The destructor closes too, ignoring errors.
  virtual Status close() = 0;
};

struct RecoveryReport {
  bool complete = true;          // footer and summary present and valid
  uint64_t bytes_total = 0;
  uint64_t bytes_recovered = 0;  // up to the end of the last complete record/chunk
  uint64_t messages_recovered = 0;
  std::string detail;            // why reading stopped early, naming the byte offset
};

// Yields events in (stamp, channel, sequence) order whatever the recording order. Checks
// the magic and version, every record's opcode, the data section CRC, the summary CRC
// (open) and each chunk's CRC (when the chunk is first needed, by next()). Stamps going
// backwards within a channel while sequences go forwards are an error from next().
// Errors name the file and the byte offset; after an error next() keeps returning it.
class FixtureSource : public hal::EventSource {
 public:
  // Maps the file and scans its records (or the readable prefix of a truncated one, see
  // recovery()); chunks are decoded lazily, only those overlapping the stream position
  // are held in memory.
  static Result<std::unique_ptr<FixtureSource>> open(const std::string& path);
  virtual const FixtureMetadata& metadata() const = 0;
  virtual const RecoveryReport& recovery() const = 0;
};

}  // namespace orthosonar::replay
