// libFuzzer harness: the line framer every line protocol (A50, $PRTI, depth) reads through.
#include <algorithm>

#include "hal/drivers/line_framer.hpp"
#include "hal/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = orthosonar::fuzz::as_stream(data, size);
  if (!stream) return 0;
  const size_t step = stream->step;
  const auto in = stream->bytes;
  orthosonar::hal::drivers::LineFramer framer(64);
  orthosonar::fuzz::in_pieces(
      in, step, [&](auto piece) { framer.push(piece); },
      [&] {
        while (framer.pop()) {
        }
      });
  return 0;
}
