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
};

class FixtureWriter {
 public:
  static Result<std::unique_ptr<FixtureWriter>> open(const std::string& path,
                                                     const FixtureMetadata& metadata,
                                                     const WriterOptions& options = {});
  virtual ~FixtureWriter() = default;
  // Appends one event. Errors name the path.
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

class FixtureSource : public hal::EventSource {
 public:
  // Reads the whole file (or the readable prefix of a truncated one, see recovery()).
  static Result<std::unique_ptr<FixtureSource>> open(const std::string& path);
  virtual const FixtureMetadata& metadata() const = 0;
  virtual const RecoveryReport& recovery() const = 0;
};

}  // namespace orthosonar::replay
