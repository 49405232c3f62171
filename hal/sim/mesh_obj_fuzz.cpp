// libFuzzer harness: Wavefront OBJ meshes.
#include "hal/fuzz_support.hpp"
#include "hal/sim/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static orthosonar::fuzz::InputFile file(".obj");
  (void)orthosonar::sim::read_mesh_obj(file.write(data, size));
  return 0;
}
