// libFuzzer harness: `inspect --protocol` decoding (offsets, counts, line splitting with its
// length bound) of one input as every protocol, read in pieces.
#include "hal/drivers/protocol_decoder.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = fuzz::as_stream(data, size);
  if (!stream) return 0;
  const size_t step = stream->step;
  const auto in = stream->bytes;
  for (auto p : {Protocol::kOculus, Protocol::kVn100, Protocol::kA50, Protocol::kPrti, Protocol::kDepth,
                 Protocol::kDsp1760, Protocol::kRtiEnsemble}) {
    auto decoder = make_decoder(p);
    uint64_t end = 0;
    auto drain = [&] {
      while (auto m = decoder->pop()) {
        // Messages come in stream order and lie inside what was pushed.
        if (m->offset < end || m->offset + m->size > in.size()) __builtin_trap();
        end = m->offset + m->size;
      }
    };
    fuzz::in_pieces(in, step, [&](auto piece) { decoder->push(piece); }, drain);
    decoder->finish();
    drain();
    (void)decoder->counts();
  }
  return 0;
}
