#pragma once
// Decoding a raw device capture (the bytes of a serial port or a TCP stream, as a logger
// saved them) message by message, for `orthosonar inspect --protocol`: every message with its
// byte offset and decoded fields, and counts of what was good, bad, skipped or left over.
// The same stream parsers as the live drivers (docs/DRIVERS.md), so what inspect accepts is
// what a live run accepts.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::hal::drivers {

enum class Protocol { kOculus, kVn100, kA50, kPrti, kDepth, kDsp1760, kRtiEnsemble };
// "oculus", "vn100", "a50", "prti", "depth", "dsp1760", "rti-ensemble"; an error lists the names.
Result<Protocol> protocol_from_name(std::string_view name);
const char* protocol_name(Protocol p);

struct DecoderLimits {
  static constexpr size_t kMaxLine = 1 << 16;  // longer lines are bad, their bytes skipped unbuffered
};

struct DecodedMessage {
  uint64_t offset = 0;  // of the message's first byte in the stream
  uint64_t size = 0;    // bytes (line protocols: without the line end)
  std::string type;     // e.g. "ping", "status", "binary", "velocity", "dead_reckoning", "PRTI01", "depth"
  std::vector<std::pair<std::string, std::string>> fields;  // wire order, numbers at full precision
};

struct DecodeCounts {
  uint64_t good = 0;           // messages decoded
  uint64_t bad = 0;            // framed but rejected: CRC or checksum, malformed fields
  uint64_t unsupported = 0;    // well-framed messages of a kind we cannot decode (VN-100 groups)
  uint64_t duplicates = 0;     // A50 reports repeating the previous one (dropped by a live run)
  uint64_t other = 0;          // well-formed messages that carry no measurement (A50 responses, other sentences)
  uint64_t skipped_bytes = 0;  // bytes between messages: garbage, ASCII, rejected frames, blank lines
  uint64_t trailing_bytes = 0; // an incomplete message at the end of the capture
  // Protocols whose packets carry a counter (DSP-1760): its breaks and the packets they
  // skip. Unset for the others.
  std::optional<uint64_t> sequence_gaps;
  uint64_t missing_packets = 0;
  std::string last_error;      // the latest rejection, with its offset
};

class ProtocolDecoder {
 public:
  virtual ~ProtocolDecoder() = default;
  // Feed the capture in pieces of any size; pop() until nullopt after each push.
  virtual void push(std::span<const uint8_t> bytes) = 0;
  virtual std::optional<DecodedMessage> pop() = 0;
  // End of the capture: what is still buffered becomes trailing bytes (or, for a line
  // protocol, a last line without its line end is decoded). pop() again afterwards.
  virtual void finish() = 0;
  virtual DecodeCounts counts() const = 0;
};

std::unique_ptr<ProtocolDecoder> make_decoder(Protocol p);

}  // namespace orthosonar::hal::drivers
