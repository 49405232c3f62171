#pragma once
// `orthosonar inspect` for raw Oculus captures (concatenated messages as sent on TCP 52100).
// tools/cmd_inspect.cpp handles MCAP files and falls through to this for anything else.
#include <string>

namespace orthosonar::cli {

// Prints one line per ping (or, with json, one JSON document) and a summary of messages,
// malformed frames and skipped bytes. Returns 0 when at least one ping decoded, 2 when the
// file cannot be read or holds no Oculus ping.
int inspect_oculus_capture(const std::string& path, bool json);

}  // namespace orthosonar::cli
