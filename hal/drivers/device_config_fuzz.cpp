// libFuzzer harness: devices.yaml (the live-run device configuration).
#include <string>

#include "hal/drivers/device_config.hpp"
#include "hal/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)orthosonar::hal::drivers::parse_live_config(std::string(orthosonar::fuzz::text(data, size)));
  return 0;
}
