// libFuzzer harness: run configuration YAML (every key range-checked).
#include <string>

#include "hal/fuzz_support.hpp"
#include "replay/run/run_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  orthosonar::run::RunConfig config;
  (void)orthosonar::run::apply_config_yaml(std::string(orthosonar::fuzz::text(data, size)), config);
  return 0;
}
