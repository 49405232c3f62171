// libFuzzer harness: STL meshes (binary and ASCII).
#include "hal/fuzz_support.hpp"
#include "hal/sim/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static orthosonar::fuzz::InputFile file(".stl");
  (void)orthosonar::sim::read_mesh_stl(file.write(data, size));
  return 0;
}
