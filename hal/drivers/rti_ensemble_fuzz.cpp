// libFuzzer harness: Rowe RTI binary ensembles (16 x 0x80 sync, header complements, CRC-16,
// data sets skipped by their declared size, partial ensembles), the stream parser read in
// pieces, the single-ensemble entry point, the DvlReading conversion, description and
// re-encoding of what decoded.
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = fuzz::as_stream(data, size);
  if (!stream) return 0;
  const auto in = stream->bytes;
  rti::StreamParser parser;
  uint64_t decoded_bytes = 0;
  auto drain = [&] {
    while (auto e = parser.pop()) {
      decoded_bytes += parser.last_ensemble_bytes();
      (void)rti::to_dvl_reading(*e, Quat::Identity(), Time{});
      (void)rti::describe(*e);
      // What decoded re-encodes to an ensemble that decodes to the same data sets.
      auto again = rti::parse_ensemble(rti::encode_ensemble(*e));
      if (!again || again->bottom_track.has_value() != e->bottom_track.has_value()) __builtin_trap();
      if (e->ensemble_data) (void)e->ensemble_data->unix_time_ns();
    }
  };
  fuzz::in_pieces(in, stream->step, [&](auto piece) { parser.push(piece); }, drain);
  parser.finish();
  drain();
  // Every byte is in an ensemble, skipped, dropped or still buffered.
  const auto& s = parser.stats();
  if (decoded_bytes + s.skipped_bytes + s.dropped_bytes + parser.buffered() != in.size()) __builtin_trap();
  (void)rti::parse_ensemble(in);
  return 0;
}
