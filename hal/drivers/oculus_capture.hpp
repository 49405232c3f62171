#pragma once
// A raw Oculus capture (concatenated messages as sent on TCP 52100) described ping by ping:
// what `orthosonar inspect` shows for a file that is not MCAP (tools/cmd_inspect.cpp).
#include <ostream>
#include <string>

namespace orthosonar::hal::drivers::oculus {

// Writes to `out` one line per ping (or, with json, one JSON document) and a summary of
// messages, malformed frames and skipped bytes; errors go to `err`. Returns 0 when at least one ping decoded, 2 when the
// file cannot be read or holds no Oculus ping.
int inspect_oculus_capture(const std::string& path, bool json, std::ostream& out, std::ostream& err);

}  // namespace orthosonar::hal::drivers::oculus
