// libFuzzer harness: MCAP files (records, chunks, compression, summary, attachments,
// truncation recovery) through the fixture source a replay uses, to the last event.
#include "hal/fuzz_support.hpp"
#include "replay/fixture.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static orthosonar::fuzz::InputFile file(".mcap");
  auto source = orthosonar::replay::FixtureSource::open(file.write(data, size));
  if (!source.ok()) return 0;
  auto& s = **source;
  (void)s.attachments();
  // Bounded: a valid input cannot hold more events than bytes.
  for (size_t n = 0; n <= size; ++n) {
    auto pulled = s.next();
    if (pulled.end_of_stream || pulled.error) break;
  }
  return 0;
}
