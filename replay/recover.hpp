#pragma once
// Rewriting a cut recording as a whole fixture (`orthosonar recover`, issue 40): what a
// killed recorder or a full disk left (a prefix of chunks, no summary, no footer) is read
// up to its last complete record (FixtureSource's recovery) and written again through the
// one fixture writer: chunked, with its attachments, metadata, summary and footer. The
// events are the recovered ones, unchanged, so replaying the output gives the digest of
// replaying the input with --allow-incomplete.
#include <string>

#include "core/result.hpp"
#include "replay/fixture.hpp"

namespace orthosonar::replay {

struct RecoverResult {
  RecoveryReport input;   // what the input held (complete = it was whole already)
  uint64_t events = 0;    // events written
  uint64_t attachments = 0;
};

// Reads `in`, writes `out` (through `out` + ".partial" and a rename: `out` is whole or
// absent). The output's metadata is the input's plus "recovered_from" when the input was
// cut (naming the file and the byte offset of the cut). Errors name the file and offset.
Result<RecoverResult> recover_fixture(const std::string& in, const std::string& out, const WriterOptions& options = {});

}  // namespace orthosonar::replay
