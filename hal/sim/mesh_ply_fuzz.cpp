// libFuzzer harness: PLY meshes and point clouds (header with bounded counts, ascii and
// binary bodies), in memory and from a file.
#include "hal/fuzz_support.hpp"
#include "hal/sim/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static orthosonar::fuzz::InputFile file(".ply");
  (void)orthosonar::sim::decode_mesh_ply(orthosonar::fuzz::text(data, size), "fuzz.ply");
  (void)orthosonar::sim::read_ply_points(file.write(data, size));
  return 0;
}
