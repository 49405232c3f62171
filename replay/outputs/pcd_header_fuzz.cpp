// libFuzzer harness: PCD headers (fields, sizes, counts bounded by the file size).
#include "hal/fuzz_support.hpp"
#include "replay/outputs/pcd_header.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)orthosonar::outputs::pcd::parse_header(orthosonar::fuzz::text(data, size), size, "fuzz.pcd");
  return 0;
}
