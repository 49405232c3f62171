// libFuzzer harness: PNG and JPEG decoding (the images of imported ROS bags, the stored
// golden images), both output kinds, with a limit that keeps one execution small.
#include "hal/codec/image_codec.hpp"

#include <span>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace orthosonar::codec;
  const std::span<const uint8_t> bytes(data, size);
  constexpr uint64_t kMaxPixels = uint64_t{1} << 20;
  for (DecodeAs as : {DecodeAs::kGray, DecodeAs::kBgr}) {
    auto r = decode_image(bytes, as, "fuzz", kMaxPixels);
    if (r.ok() && (r->empty() || static_cast<uint64_t>(r->total()) > kMaxPixels)) __builtin_trap();
  }
  return 0;
}
