// libFuzzer harness: the Oculus TCP byte stream (framing, resync, every message type) and
// the conversion of each decoded ping to a core SonarPing.
#include <algorithm>
#include <variant>

#include "hal/drivers/oculus_stream.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = fuzz::as_stream(data, size);
  if (!stream) return 0;
  const size_t step = stream->step;
  const auto in = stream->bytes;
  oculus::StreamParser parser;
  fuzz::in_pieces(
      in, step, [&](auto piece) { parser.push(piece); },
      [&] {
        while (auto m = parser.pop())
          if (const auto* ping = std::get_if<oculus::PingResult>(&*m))
            (void)oculus::to_sonar_ping(*ping, SonarMount::kHorizontal, kPartM1200d, Time{});
      });
  return 0;
}
