#pragma once
// What `orthosonar inspect` and run summaries report about a fixture: duration, channels
// (topic, schema, count, rate), gaps longer than twice a channel's nominal period,
// metadata, container facts and how much of a truncated file was recovered.
#include <cstdint>
#include <string>
#include <vector>

#include "core/time.hpp"
#include "replay/fixture.hpp"
#include "replay/mcap_reader.hpp"

namespace orthosonar::replay {

struct Gap {
  Time from, to;  // stamps of the two messages around the gap
};

struct ChannelSummary {
  std::string topic, schema;
  uint64_t count = 0;
  Time first, last;
  double rate_hz = 0.0;     // (count - 1) / (last - first)
  Time nominal_period;      // median interval between consecutive messages
  std::vector<Gap> gaps;    // intervals > 2 x nominal_period
};

struct FixtureSummary {
  std::string path, profile, library;
  uint64_t file_bytes = 0;
  uint64_t messages = 0;
  uint64_t chunks = 0;
  std::vector<std::string> compressions;  // distinct chunk compressions ("" = none)
  mcap::ReadInfo read;                    // how the file was read: summary or linear scan, ...
  Time start, end;                        // first and last stamp
  Time duration() const { return end - start; }
  FixtureMetadata metadata;
  RecoveryReport recovery;
  std::vector<ChannelSummary> channels;   // channels present, in Channel order
  struct AttachmentSummary {
    std::string name, media_type;
    uint64_t bytes = 0;
  };
  std::vector<AttachmentSummary> attachments;  // embedded files (the scene), in file order
};

// Reads every message (CRC-checked, decoded). Errors name the file and byte offset.
Result<FixtureSummary> summarize_fixture(const std::string& path);

// True when the first bytes of the file are the MCAP magic (for dispatching by content).
bool has_mcap_magic(const std::string& path);

}  // namespace orthosonar::replay
