// libFuzzer harness: the line framer every line protocol (A50, $PRTI, depth) reads through.
#include <algorithm>

#include "hal/drivers/line_framer.hpp"
#include "hal/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t step = size_t{data[0]} + 1;
  auto in = orthosonar::fuzz::bytes(data + 1, size - 1);
  orthosonar::hal::drivers::LineFramer framer(64);
  orthosonar::fuzz::in_pieces(
      in, step, [&](auto piece) { framer.push(piece); },
      [&] {
        while (framer.pop()) {
        }
      });
  return 0;
}
