// libFuzzer harness: depth lines ($DEPTH,<m>*XX and the JSON form).
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  LineFramer framer;
  framer.push(orthosonar::fuzz::bytes(data, size));
  framer.push(orthosonar::fuzz::bytes(reinterpret_cast<const uint8_t*>("\n"), 1));
  while (auto line = framer.pop())
    if (auto r = dvl::parse_depth(*line)) (void)dvl::describe(*r);
  return 0;
}
