#pragma once
// A raw device capture file (serial or TCP byte stream) decoded message by message with the
// live drivers' parsers (protocol_decoder.hpp), as text, JSON and CSV: what
// `orthosonar inspect --protocol oculus|vn100|a50|prti|depth|rti-ensemble FILE [--json] [--csv OUT]` shows.
#include <ostream>
#include <string>

namespace orthosonar::hal::drivers {

// Writes to `out` (errors to `err`). Text: one line per message ("@offset type name=value ..."), then the counts. JSON: one
// document with every message and the counts. csv_path (optional): one row per message, a
// column per field name (union over the messages, first-seen order).
// Returns 0 when every framed message decoded, 1 when some were bad or unsupported, 2 when the
// file cannot be read, the protocol is unknown, or no message of the protocol decoded.
int inspect_protocol_capture(const std::string& path, const std::string& protocol, bool json,
                             const std::string& csv_path, std::ostream& out, std::ostream& err);

}  // namespace orthosonar::hal::drivers
