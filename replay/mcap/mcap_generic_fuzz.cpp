// libFuzzer harness: any MCAP file (records, chunks in every compression, Schema and
// Channel records in and out of chunks, truncation recovery) through visit_messages, the
// reader `orthosonar import` uses, touching every message byte.
#include "hal/fuzz_support.hpp"
#include "replay/mcap/mcap_generic.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace mcap = orthosonar::replay::mcap;
  static orthosonar::fuzz::InputFile file(".mcap");
  uint64_t sum = 0;
  orthosonar::replay::RecoveryReport recovery;
  (void)mcap::visit_messages(
      file.write(data, size),
      [&](const mcap::RawChannel& c, const mcap::RawSchema* s) -> orthosonar::Status {
        sum += c.topic.size() + (s != nullptr ? s->data.size() : 0);
        return {};
      },
      [&](const mcap::RawMessage& m) -> orthosonar::Status {
        for (size_t i = 0; i < m.size; ++i) sum += m.data[i];
        return {};
      },
      &recovery);
  if (recovery.bytes_recovered > recovery.bytes_total) __builtin_trap();
  static volatile uint64_t sink = 0;  // keeps the reads of every message byte
  sink = sink + sum;
  return 0;
}
