// libFuzzer harness: Water Linked A50 JSON report lines (every firmware variant).
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  LineFramer framer;
  framer.push(orthosonar::fuzz::bytes(data, size));
  framer.push(orthosonar::fuzz::bytes(reinterpret_cast<const uint8_t*>("\n"), 1));
  dvl::A50Parser parser;  // duplicate detection across the lines of one input
  // One JSON parse per line (parse_a50_line and decode_a50 are the same decoder without the
  // duplicate state; nlohmann's instrumented lexer dominates the cost of an execution).
  while (auto line = framer.pop()) {
    auto r = parser.parse(*line);
    if (r.ok() && *r) (void)dvl::describe(**r);
  }
  return 0;
}
