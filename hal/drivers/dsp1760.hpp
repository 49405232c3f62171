#pragma once
// KVH DSP-1760 fibre-optic gyro, normal-mode binary output (the paper's vehicle's FOG;
// docs/DRIVERS.md "KVH DSP-1760"). Every packet is 36 bytes, big-endian, MSB first:
//
//   offset  size  field
//        0     4  header FE 81 FF 55
//        4     4  X  IEEE-754 float32: delta angle or rate, radians or degrees (device setting)
//        8     4  Y
//       12     4  Z
//       16    12  reserved (the KVH IMUs' accelerations in the same "Format A"; unused here)
//       28     1  status: bit 0 X, bit 1 Y, bit 2 Z valid (1 = valid); bit 3 always 0
//       29     1  sequence counter 0..127, +1 per packet, 127 -> 0
//       30     2  temperature, int16: whole or 1/100 degrees C or F (device setting)
//       32     4  CRC-32/MPEG-2 of bytes 0..31 (poly 0x04C11DB7, init 0xFFFFFFFF, not
//                 reflected, no final xor), big-endian
//
// Whether X/Y/Z are delta angles or rates, the angle unit and the temperature unit are the
// device's configuration, not visible in a packet: they are decoder options (Config), never
// guessed from the data. Frames: values are about the gyro's own axes (frame G); rotating
// them into V and removing the Earth's rotation is the dead reckoning's business.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/drivers/bytes.hpp"

namespace orthosonar::hal::drivers::dsp1760 {

inline constexpr std::array<uint8_t, 4> kHeader = {0xFE, 0x81, 0xFF, 0x55};
inline constexpr size_t kPacketBytes = 36;
inline constexpr size_t kOffsetX = 4;
inline constexpr size_t kOffsetReserved = 16;
inline constexpr size_t kReservedBytes = 12;
inline constexpr size_t kOffsetStatus = 28;
inline constexpr size_t kOffsetSequence = 29;
inline constexpr size_t kOffsetTemperature = 30;
inline constexpr size_t kOffsetCrc = 32;
inline constexpr uint8_t kStatusX = 0x01;
inline constexpr uint8_t kStatusY = 0x02;
inline constexpr uint8_t kStatusZ = 0x04;
inline constexpr uint8_t kStatusXyz = kStatusX | kStatusY | kStatusZ;
inline constexpr unsigned kSequenceModulo = 128;

// CRC-32/MPEG-2 (catalogue check value of "123456789": 0x0376E6E7).
uint32_t crc32_mpeg2(std::span<const uint8_t> data);

enum class Output { kDeltaAngle, kRate };  // the device's =dr/output setting: angle since the last packet, or rate
enum class AngleUnit { kRadians, kDegrees };
enum class TemperatureUnit { kCelsius, kCentiCelsius, kFahrenheit, kCentiFahrenheit };  // =tempunits C, C_100, F, F_100

struct Config {
  Output output = Output::kDeltaAngle;          // the authors' configuration (kvh_gyro `delta`)
  AngleUnit angle_unit = AngleUnit::kRadians;
  TemperatureUnit temperature_unit = TemperatureUnit::kCelsius;
  uint8_t axes = kStatusXyz;  // status bits that must all be set for a valid reading (1- and 2-axis variants: fewer)
  friend bool operator==(const Config&, const Config&) = default;
};

// YAML / command-line names: "delta" | "rate", "rad" | "deg", "c" | "c_100" | "f" | "f_100".
const char* output_name(Output o);
const char* angle_unit_name(AngleUnit u);
const char* temperature_unit_name(TemperatureUnit u);
Result<Output> output_from_name(const std::string& s);
Result<AngleUnit> angle_unit_from_name(const std::string& s);
Result<TemperatureUnit> temperature_unit_from_name(const std::string& s);

// One packet's fields as sent (before any unit conversion).
struct Packet {
  std::array<float, 3> xyz{};
  std::array<uint8_t, kReservedBytes> reserved{};
  uint8_t status = 0;
  uint8_t sequence = 0;
  int16_t temperature_raw = 0;
  uint32_t crc = 0;  // as received (encode_packet() computes its own)
  friend bool operator==(const Packet&, const Packet&) = default;
};

// Decodes the packet at data[0]: an error names the field and its offset (header, CRC,
// sequence out of 0..127) or the missing length.
Result<Packet> parse_packet(std::span<const uint8_t> data);
// The 36 bytes of `p` with their CRC (p.crc is ignored).
Bytes encode_packet(const Packet& p);

// Degrees Celsius from the raw temperature in the configured unit.
double temperature_c(int16_t raw, TemperatureUnit unit);

// The reading a packet gives (stamp: the receive clock's, as for the other drivers):
// value_G in rad or rad/s per `c`, is_rate per c.output, valid when every status bit of
// c.axes is set, the packet's sequence and its temperature in degrees C.
GyroReading to_gyro_reading(const Packet& p, const Config& c, Time stamp);
// The packet a DSP-1760 configured as `c` sends for `r` (emulator side): the float32 of the
// value in c's unit, status c.axes when valid else 0, sequence r.sequence mod 128, the
// temperature rounded to c's unit (clamped to int16).
Packet packet_from(const GyroReading& r, const Config& c);

// Every field in wire order as (name, text) for `orthosonar inspect --protocol dsp1760`:
// X Y Z (%.9g, as sent), status (hex), valid_x valid_y valid_z, sequence, temperature_raw,
// crc (hex); reserved (hex) only when not all zero.
std::vector<std::pair<std::string, std::string>> describe(const Packet& p);

struct StreamStats {
  uint64_t accepted = 0;         // packets with a good CRC and fields in range, returned by pop()
  uint64_t bad_crc = 0;          // a header whose 36 bytes fail the CRC (corrupted, or cut short by what followed)
  uint64_t bad_field = 0;        // good CRC but a field out of its documented range (sequence > 127)
  uint64_t sequence_gaps = 0;    // accepted packets whose sequence is not the previous one's + 1 (mod 128)
  uint64_t missing_packets = 0;  // packets those gaps skip, (seq - expected) mod 128: a longer outage aliases
  uint64_t skipped_bytes = 0;    // bytes discarded while looking for a header (garbage, rejected headers)
  uint64_t dropped_bytes = 0;    // bytes discarded unread because the buffer was full
};

// Byte-stream framing with resynchronisation: bytes before a header are skipped; after a
// CRC failure or a bad field only the header's first byte is dropped and the search goes on
// (a real packet may start inside the rejected one). Every byte pushed ends up accepted (in
// a packet), skipped, dropped, or still buffered. Sequence continuity is checked across
// accepted packets only, so a packet lost to a bad CRC also shows as a gap. Not thread-safe.
class StreamParser {
 public:
  static constexpr size_t kMaxBuffered = 64 * 1024;
  void push(std::span<const uint8_t> bytes);
  // The next packet, or nullopt when more bytes are needed (pop() until nullopt after each push).
  std::optional<Packet> pop();
  const StreamStats& stats() const { return stats_; }
  size_t buffered() const { return buf_.size() - start_; }
  // Packets missing just before the one the last pop() returned (0: none, or the first).
  unsigned last_missing() const { return last_missing_; }
  uint64_t messages() const { return stats_.accepted; }
  uint64_t malformed() const { return stats_.bad_crc + stats_.bad_field; }
  // The latest rejection (bad CRC or field) with its byte offset in the stream pushed.
  const std::string& last_error() const { return last_error_; }

 private:
  void reject(std::string why);
  Bytes buf_;
  size_t start_ = 0;
  uint64_t base_ = 0;  // stream offset of buf_[0], for the byte offsets in last_error()
  StreamStats stats_;
  std::optional<uint8_t> last_sequence_;
  unsigned last_missing_ = 0;
  std::string last_error_;
};

}  // namespace orthosonar::hal::drivers::dsp1760
