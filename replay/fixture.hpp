#pragma once
// Fixtures: recordings of event streams as MCAP files (SPEC §11). The writer appends
// events in the order the core consumed them; the source replays them in
// (stamp, channel, sequence) order.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/event_source.hpp"

namespace orthosonar::replay {

// Free-form metadata written as an MCAP metadata record named "orthosonar":
// scene, seed, extrinsics, software version, ... Ordered map: deterministic bytes.
using FixtureMetadata = std::map<std::string, std::string>;

// A file embedded in a fixture as an MCAP Attachment record (the simulator embeds its
// scene this way, hal/sim/scene.hpp embed_scene). Times are stream times or 0, never the
// wall clock, so the fixture's bytes stay a pure function of the recording.
struct Attachment {
  std::string name;        // e.g. "orthosonar_scene.yaml"
  std::string media_type;  // e.g. "application/yaml"
  std::vector<uint8_t> data;
  uint64_t log_time_ns = 0;
  uint64_t create_time_ns = 0;
  friend bool operator==(const Attachment&, const Attachment&) = default;
};

// The first attachment called `name`, or nullptr.
const Attachment* find_attachment(const std::vector<Attachment>& attachments, std::string_view name);
// name -> data (the first of equal names), the form hal/sim's scene_from_fixture takes.
std::map<std::string, std::vector<uint8_t>> attachment_files(const std::vector<Attachment>& attachments);

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
  // Writes an Attachment record (with its CRC) into the data section now, outside any
  // chunk, and lists it in the summary (Attachment Index, Statistics). Write attachments
  // right after open() so that a recording killed mid-write still holds them. Errors name
  // the path; an attachment over 1 GiB or with an empty name is rejected.
  virtual Status attach(const Attachment& attachment) = 0;
  // Writes the summary section and footer. The destructor closes too, ignoring errors.
  virtual Status close() = 0;
};

struct RecoveryReport {
  bool complete = true;          // footer and summary present and valid
  uint64_t bytes_total = 0;
  uint64_t bytes_recovered = 0;  // up to the end of the last complete record/chunk
  uint64_t messages_recovered = 0;
  std::string detail;            // why reading stopped early, naming the byte offset
  // Log times spanned by the recovered messages (chunk and message-run headers; 0 when
  // none): the sensor time a cut recording still holds.
  uint64_t first_ns = 0, last_ns = 0;
  double sensor_seconds() const { return last_ns > first_ns ? static_cast<double>(last_ns - first_ns) * 1e-9 : 0.0; }
};

// Issue 40: whether an input fixture is whole. The one decision every command applies to
// the fixtures it reads (`inspect` prints "recovery: INCOMPLETE" on it; replay, verify,
// sweep, fuse, export, perception-check, run --metadata-from, batch tasks warn and exit 1
// unless --allow-incomplete). Empty for a whole file; for a cut one, the warning naming
// the file, the byte offset of the cut and what was recovered (seconds of sensor time,
// messages).
std::optional<std::string> cut_input_warning(const std::string& path, const RecoveryReport& recovery);

// Yields events in (stamp, channel, sequence) order whatever the recording order. Checks
// the magic and version, every record's opcode, the data section CRC, the summary CRC
// (open) and each chunk's CRC (when the chunk is first needed, by next()). Stamps going
// backwards within a channel while sequences go forwards are an error from next().
// Errors name the file and the byte offset; after an error next() keeps returning it.
class FixtureSource : public hal::EventSource {
 public:
  // Maps the file and scans its records (or the readable prefix of a truncated one, see
  // recovery()); chunks (and runs of messages outside chunks) are decoded lazily, only
  // those overlapping the stream position are held in memory, and file bytes are released
  // once consumed: memory does not grow with the recording (issue 16).
  static Result<std::unique_ptr<FixtureSource>> open(const std::string& path);
  virtual const FixtureMetadata& metadata() const = 0;
  virtual const RecoveryReport& recovery() const = 0;
  // What the source holds (tests, benchmarks): decoded events waiting to be yielded now
  // and at most so far, and the chunks (or loose-message runs) decoded so far.
  struct Holding {
    size_t events = 0, peak_events = 0;
    size_t chunks_read = 0;
  };
  virtual Holding holding() const = 0;
  // The Attachment records in file order (CRC-checked when the scan met them; a
  // truncated file keeps those before the cut). Old fixtures have none.
  virtual const std::vector<Attachment>& attachments() const;
};

}  // namespace orthosonar::replay
