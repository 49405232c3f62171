#pragma once
// VectorNav VN-100 binary output: sync 0xFA, a groups byte, one u16 field mask per present
// group, the fields in bit order (little-endian), then CRC16-XMODEM (CCITT, poly 0x1021,
// init 0, big-endian) over everything after the sync byte. We decode the Common group (1):
// every field size is known, so any field selection parses; other groups are rejected.
// Frames: the VN-100 reports attitude of its body (x forward, y right, z down) in local NED;
// conversion to REP-103 (V: x forward, y left, z up; W: ENU) is in to_imu_reading().
#include <array>
#include <optional>
#include <span>
#include <string>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/drivers/bytes.hpp"

namespace orthosonar::hal::drivers::vn100 {

inline constexpr uint8_t kSync = 0xFA;
inline constexpr uint8_t kGroupCommon = 0x01;
// Common-group field bits.
inline constexpr uint16_t kTimeStartup = 1u << 0;
inline constexpr uint16_t kYawPitchRoll = 1u << 3;
inline constexpr uint16_t kQuaternion = 1u << 4;
inline constexpr uint16_t kAngularRate = 1u << 5;
inline constexpr uint16_t kAccel = 1u << 8;

// CRC16-XMODEM (the VectorNav 16-bit CRC).
uint16_t crc16_xmodem(std::span<const uint8_t> data);

struct Message {
  uint16_t common_fields = 0;
  std::optional<uint64_t> time_startup_ns;
  std::optional<std::array<float, 3>> ypr_deg;       // yaw, pitch, roll (NED, degrees)
  std::optional<std::array<float, 4>> quat_xyzw;     // body (FRD) in NED, scalar last
  std::optional<std::array<float, 3>> angular_rate;  // rad/s, body FRD
  std::optional<std::array<float, 3>> accel;         // m/s^2, body FRD
};

// Decodes one complete packet starting with the sync byte; `used` receives its length.
Result<Message> parse_packet(std::span<const uint8_t> data, size_t* used = nullptr);
// Encodes a packet with the fields that are set (Common group only).
Bytes encode_packet(const Message& m);

// Byte-stream framing with resynchronisation on 0xFA after garbage or a CRC failure.
class StreamParser {
 public:
  void push(std::span<const uint8_t> bytes);
  std::optional<Message> pop();
  uint64_t messages() const { return messages_; }
  uint64_t malformed() const { return malformed_; }
  uint64_t garbage_bytes() const { return garbage_; }
  const std::string& last_error() const { return last_error_; }

 private:
  Bytes buf_;
  size_t start_ = 0;
  uint64_t messages_ = 0, malformed_ = 0, garbage_ = 0;
  std::string last_error_;
};

// REP-103 IMU reading from a packet (quaternion preferred, else yaw/pitch/roll); q_V_S is the
// mounting rotation of the sensor's FLU axes in V (identity when aligned). Errors when the
// packet carries no orientation.
Result<ImuReading> to_imu_reading(const Message& m, const Quat& q_V_S, Time stamp);
// The packet a VN-100 mounted with q_V_S would send for `r` (emulator side).
Message message_from(const ImuReading& r, const Quat& q_V_S);

}  // namespace orthosonar::hal::drivers::vn100
