// libFuzzer harness: Rowe SeaPilot $PRTI sentences (NMEA checksum, fields, invalid markers).
#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  LineFramer framer;
  framer.push(orthosonar::fuzz::bytes(data, size));
  framer.push(orthosonar::fuzz::bytes(reinterpret_cast<const uint8_t*>("\n"), 1));
  while (auto line = framer.pop()) {
    (void)dvl::parse_prti01(*line);
    (void)dvl::parse_prti02(*line);
    if (auto r = dvl::parse_prti(*line)) {
      (void)dvl::describe(*r);
      (void)dvl::encode_prti(*r);
    }
  }
  return 0;
}
