// libFuzzer harness: the KVH DSP-1760 byte stream (header search, CRC, sequence counting,
// resync across garbage, split reads), the single-packet entry point and the conversion of
// each packet to a GyroReading under every configuration; a packet that decodes re-encodes
// to the same bytes.
#include <algorithm>

#include "hal/drivers/dsp1760.hpp"
#include "hal/fuzz_support.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto stream = fuzz::as_stream(data, size);
  if (!stream) return 0;
  const auto in = stream->bytes;
  dsp1760::Config c;
  c.output = (size & 1) ? dsp1760::Output::kRate : dsp1760::Output::kDeltaAngle;
  c.angle_unit = (size & 2) ? dsp1760::AngleUnit::kDegrees : dsp1760::AngleUnit::kRadians;
  c.temperature_unit = static_cast<dsp1760::TemperatureUnit>((size >> 2) & 3);
  dsp1760::StreamParser parser;
  uint64_t accepted = 0;
  fuzz::in_pieces(
      in, stream->step, [&](auto piece) { parser.push(piece); },
      [&] {
        while (auto p = parser.pop()) {
          ++accepted;
          (void)dsp1760::to_gyro_reading(*p, c, Time{});
          (void)dsp1760::describe(*p);
        }
      });
  const auto& s = parser.stats();
  // Every byte is in an accepted packet, skipped, dropped or still buffered.
  if (s.accepted != accepted ||
      s.accepted * dsp1760::kPacketBytes + s.skipped_bytes + s.dropped_bytes + parser.buffered() != in.size())
    __builtin_trap();
  if (auto p = dsp1760::parse_packet(in)) {
    const Bytes again = dsp1760::encode_packet(*p);
    if (!std::equal(again.begin(), again.end(), in.begin())) __builtin_trap();
    (void)dsp1760::packet_from(dsp1760::to_gyro_reading(*p, c, Time{}), c);
  }
  return 0;
}
