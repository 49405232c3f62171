// libFuzzer harness: simulator configuration YAML (`simulate --config`), then validation.
#include <string>

#include "hal/fuzz_support.hpp"
#include "hal/sim/sim_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  orthosonar::sim::SimConfig config;
  if (orthosonar::sim::apply_sim_config_yaml(std::string(orthosonar::fuzz::text(data, size)), config).ok())
    (void)orthosonar::sim::validate(config);
  return 0;
}
