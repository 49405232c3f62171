// libFuzzer harness: scene YAML files (primitives, mesh references, route, classes).
#include "hal/fuzz_support.hpp"
#include "hal/sim/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static orthosonar::fuzz::InputFile file(".yaml");
  (void)orthosonar::sim::load_scene_file(file.write(data, size));
  return 0;
}
