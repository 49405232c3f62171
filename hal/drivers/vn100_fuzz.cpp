// libFuzzer harness: the VN-100 binary stream (group/field masks, packet length, CRC,
// resync across ASCII) and the conversion of each packet to an IMU reading.
#include <algorithm>

#include "hal/drivers/vn100.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = fuzz::as_stream(data, size);
  if (!stream) return 0;
  const size_t step = stream->step;
  const auto in = stream->bytes;
  vn100::StreamParser parser;
  fuzz::in_pieces(
      in, step, [&](auto piece) { parser.push(piece); },
      [&] {
        while (auto m = parser.pop()) (void)vn100::to_imu_reading(*m, Quat::Identity(), Time{});
      });
  // The single-packet entry point too, on the raw input.
  (void)vn100::parse_packet(in);
  return 0;
}
