#pragma once
// VectorNav VN-100 binary output (VN-100 ICD, "Binary Output"): sync 0xFA, a groups byte, one
// u16 field mask per present group (in group-bit order), then the fields of each group in
// group order and bit order (little-endian), then CRC16-XMODEM (CCITT, poly 0x1021, init 0,
// big-endian) over everything after the sync byte.
//
// We decode the four groups a VN-100 sends: Common (groups bit 0, ICD group 1), Time (bit 1,
// group 2), IMU (bit 2, group 3) and Attitude (bit 4, group 5). The packet length follows from
// the masks alone (field sizes are fixed per bit); a groups byte with another bit (GNSS 0x08,
// INS 0x20, GNSS2 0x40: VN-200/300 only; 0x80) or a field bit whose size the ICD does not give
// (reserved or undocumented bits, the extension bit 15) makes the length unknown: such a
// packet is "unsupported", never guessed at. Fields a VN-100 leaves to the GNSS products but
// whose size is fixed (Common Position/Velocity/InsStatus, Time GpsTow/TimeUtc...) are decoded.
//
// Frames: the VN-100 reports attitude of its body (x forward, y right, z down) in local NED;
// conversion to REP-103 (V: x forward, y left, z up; W: ENU) is in to_imu_reading().
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

namespace orthosonar::hal::drivers::vn100 {

inline constexpr uint8_t kSync = 0xFA;
// Bits of the groups byte.
inline constexpr uint8_t kGroupCommon = 0x01;    // ICD group 1
inline constexpr uint8_t kGroupTime = 0x02;      // ICD group 2
inline constexpr uint8_t kGroupImu = 0x04;       // ICD group 3
inline constexpr uint8_t kGroupAttitude = 0x10;  // ICD group 5
inline constexpr uint8_t kSupportedGroups = kGroupCommon | kGroupTime | kGroupImu | kGroupAttitude;
// A few Common-group field bits (the ones the emulator sends).
inline constexpr uint16_t kTimeStartup = 1u << 0;
inline constexpr uint16_t kYawPitchRoll = 1u << 3;
inline constexpr uint16_t kQuaternion = 1u << 4;
inline constexpr uint16_t kAngularRate = 1u << 5;
inline constexpr uint16_t kAccel = 1u << 8;
// The longest packet the supported groups can form (every known field of all four groups).
inline constexpr size_t kMaxPacketBytes = 523;

// CRC16-XMODEM (the VectorNav 16-bit CRC).
uint16_t crc16_xmodem(std::span<const uint8_t> data);

using Float3 = std::array<float, 3>;

// Multi-value fields, members in wire order.
struct UncompImu {  // Common bit 9: IMU UncompAccel then UncompGyro
  Float3 accel;     // m/s^2, body
  Float3 gyro;      // rad/s, body
  friend bool operator==(const UncompImu&, const UncompImu&) = default;
};
struct MagPres {  // Common bit 10: IMU Mag, Temp, Pres
  Float3 mag;     // Gauss, body (compensated)
  float temp_c;
  float pres_kpa;
  friend bool operator==(const MagPres&, const MagPres&) = default;
};
struct Deltas {  // Common bit 11: IMU DeltaTheta (with its time) then DeltaVel
  float dtime_s;
  Float3 dtheta_deg;
  Float3 dvel_mps;
  friend bool operator==(const Deltas&, const Deltas&) = default;
};
struct DeltaTheta {  // IMU bit 6
  float dtime_s;
  Float3 dtheta_deg;
  friend bool operator==(const DeltaTheta&, const DeltaTheta&) = default;
};
struct TimeUtc {  // Time bit 6
  int8_t year;    // since 2000
  uint8_t month, day, hour, minute, second;
  uint16_t ms;
  friend bool operator==(const TimeUtc&, const TimeUtc&) = default;
};
struct Heave {  // Attitude bit 12 (firmware 3.x)
  float heave_m;
  float heave_rate_mps;
  float delayed_heave_m;
  friend bool operator==(const Heave&, const Heave&) = default;
};

// Group 2 (Time). Times in nanoseconds.
struct TimeFields {
  std::optional<uint64_t> time_startup_ns;  // bit 0
  std::optional<uint64_t> time_gps_ns;      // bit 1 (GNSS products)
  std::optional<uint64_t> gps_tow_ns;       // bit 2 (GNSS products)
  std::optional<uint16_t> gps_week;         // bit 3 (GNSS products)
  std::optional<uint64_t> time_syncin_ns;   // bit 4: since the last SyncIn trigger
  std::optional<uint64_t> time_gps_pps_ns;  // bit 5 (GNSS products)
  std::optional<TimeUtc> time_utc;          // bit 6
  std::optional<uint32_t> sync_in_cnt;      // bit 7
  std::optional<uint32_t> sync_out_cnt;     // bit 8
  std::optional<uint8_t> time_status;       // bit 9
  friend bool operator==(const TimeFields&, const TimeFields&) = default;
};

// Group 3 (IMU). Vectors in the body frame (x forward, y right, z down).
struct ImuFields {
  std::optional<uint16_t> imu_status;    // bit 0
  std::optional<Float3> uncomp_mag;      // bit 1, Gauss
  std::optional<Float3> uncomp_accel;    // bit 2, m/s^2
  std::optional<Float3> uncomp_gyro;     // bit 3, rad/s
  std::optional<float> temp_c;           // bit 4
  std::optional<float> pres_kpa;         // bit 5
  std::optional<DeltaTheta> delta_theta; // bit 6
  std::optional<Float3> delta_vel_mps;   // bit 7
  std::optional<Float3> mag;             // bit 8, Gauss (compensated)
  std::optional<Float3> accel;           // bit 9, m/s^2 (compensated)
  std::optional<Float3> angular_rate;    // bit 10, rad/s (compensated)
  std::optional<uint16_t> sens_sat;      // bit 11
  friend bool operator==(const ImuFields&, const ImuFields&) = default;
};

// Group 5 (Attitude). Attitude of the body (FRD) in local NED.
struct AttitudeFields {
  std::optional<uint16_t> vpe_status;              // bit 0
  std::optional<Float3> ypr_deg;                   // bit 1: yaw, pitch, roll (3-2-1)
  std::optional<std::array<float, 4>> quat_xyzw;   // bit 2: scalar last
  // bit 3: the rotation body -> NED, row-major: dcm[3 i + j] = R_NED_body(i, j) (checked
  // against YawPitchRoll on the real log, testdata/vn100).
  std::optional<std::array<float, 9>> dcm;
  std::optional<Float3> mag_ned;                   // bit 4, Gauss
  std::optional<Float3> accel_ned;                 // bit 5, m/s^2
  std::optional<Float3> linear_accel_body;         // bit 6, m/s^2 without gravity
  std::optional<Float3> linear_accel_ned;          // bit 7, m/s^2 without gravity
  std::optional<Float3> ypr_u_deg;                 // bit 8: 1-sigma yaw, pitch, roll uncertainty
  std::optional<Heave> heave;                      // bit 12
  std::optional<float> att_u_deg;                  // bit 13: 1-sigma attitude uncertainty
  friend bool operator==(const AttitudeFields&, const AttitudeFields&) = default;
};

// One decoded packet: every field is optional (set exactly when its mask bit was set). The
// Common group (1) is at the top level; it repeats fields of the other groups.
struct Message {
  std::optional<uint64_t> time_startup_ns;              // bit 0
  std::optional<uint64_t> time_gps_ns;                  // bit 1 (GNSS products)
  std::optional<uint64_t> time_syncin_ns;               // bit 2
  std::optional<Float3> ypr_deg;                        // bit 3: yaw, pitch, roll (NED, degrees)
  std::optional<std::array<float, 4>> quat_xyzw;        // bit 4: body (FRD) in NED, scalar last
  std::optional<Float3> angular_rate;                   // bit 5: rad/s, body FRD
  std::optional<std::array<double, 3>> position_lla;    // bit 6: deg, deg, m (GNSS products)
  std::optional<Float3> velocity_ned;                   // bit 7: m/s (GNSS products)
  std::optional<Float3> accel;                          // bit 8: m/s^2, body FRD
  std::optional<UncompImu> uncomp_imu;                  // bit 9
  std::optional<MagPres> mag_pres;                      // bit 10
  std::optional<Deltas> deltas;                         // bit 11
  std::optional<uint16_t> ins_status;                   // bit 12 (VPE/INS status)
  std::optional<uint32_t> sync_in_cnt;                  // bit 13
  std::optional<uint64_t> time_gps_pps_ns;              // bit 14 (GNSS products)
  TimeFields time;
  ImuFields imu;
  AttitudeFields attitude;
  friend bool operator==(const Message&, const Message&) = default;
};

// The groups byte and one group's field mask that encode_packet() writes for `m`.
uint8_t groups_of(const Message& m);
uint16_t fields_of(const Message& m, uint8_t group);
// Size in bytes of field `bit` of `group` (one of the kGroup* bits), or nullopt when the ICD
// gives none (a reserved bit, or a group we do not decode).
std::optional<size_t> field_size(uint8_t group, unsigned bit);

// The length of the packet starting at data[0] (the sync byte), from its groups byte and
// field masks alone.
struct PacketLength {
  enum class Status { kKnown, kNeedMoreBytes, kUnsupported };
  Status status = Status::kNeedMoreBytes;
  size_t bytes = 0;    // kKnown: sync to CRC inclusive
  std::string reason;  // kUnsupported: which bit
};
PacketLength packet_length(std::span<const uint8_t> data);

// Decodes one complete packet starting with the sync byte; `used` receives its length.
Result<Message> parse_packet(std::span<const uint8_t> data, size_t* used = nullptr);
// Encodes a packet with every field that is set, groups and fields in bit order. A message
// with no field set gives groups byte 0, which parse_packet() rejects.
Bytes encode_packet(const Message& m);

struct StreamStats {
  uint64_t accepted = 0;       // packets with a good CRC, returned by pop()
  uint64_t bad_crc = 0;        // packets whose CRC failed (corrupted, or cut short by what followed)
  uint64_t unsupported = 0;    // sync bytes whose header has a group or field bit of unknown size
  uint64_t skipped_bytes = 0;  // bytes discarded while resynchronising (ASCII, garbage, rejected syncs)
  uint64_t dropped_bytes = 0;  // bytes discarded unread because the buffer was full
};

// Byte-stream framing with resynchronisation: bytes before a sync byte are skipped; after an
// unsupported header or a CRC failure only the sync byte is dropped and the search goes on
// (a real packet may start inside the rejected one). Every byte pushed ends up accepted (in a
// packet), skipped, dropped, or still buffered. Not thread-safe.
class StreamParser {
 public:
  // The parser holds at most kMaxBuffered unread bytes; when a push would exceed that, the
  // oldest are dropped (counted). Call pop() until it returns nullopt after each push: then
  // fewer than kMaxPacketBytes remain.
  static constexpr size_t kMaxBuffered = 128 * 1024;
  void push(std::span<const uint8_t> bytes);
  // The next packet, or nullopt when more bytes are needed.
  std::optional<Message> pop();
  const StreamStats& stats() const { return stats_; }
  size_t buffered() const { return buf_.size() - start_; }
  // Length in bytes (sync to CRC) of the packet the last pop() returned.
  size_t last_packet_bytes() const { return last_packet_bytes_; }
  // Shorthands kept for the decoders: accepted, bad CRC + unsupported, skipped bytes.
  uint64_t messages() const { return stats_.accepted; }
  uint64_t malformed() const { return stats_.bad_crc + stats_.unsupported; }
  uint64_t garbage_bytes() const { return stats_.skipped_bytes; }
  const std::string& last_error() const { return last_error_; }

 private:
  void reject(std::string why);
  Bytes buf_;
  size_t start_ = 0;
  size_t last_packet_bytes_ = 0;
  StreamStats stats_;
  std::string last_error_;
};

// REP-103 IMU reading from a packet. Orientation from a quaternion (Common, else Attitude),
// else the Attitude DCM, else yaw/pitch/roll (Common, else Attitude); an error names the
// missing field when there is none. Angular rate from Common AngularRate, else IMU
// AngularRate, else UncompGyro (IMU, else Common Imu); acceleration from Common Accel, else
// IMU Accel, else UncompAccel (IMU, else Common Imu). Rates or acceleration absent from the
// packet stay exactly zero (core/slam/dead_reckoning.cpp reads that as "no gyro"). q_V_S is
// the mounting rotation of the sensor's FLU axes in V (identity when aligned).
Result<ImuReading> to_imu_reading(const Message& m, const Quat& q_V_S, Time stamp);
// The packet a VN-100 mounted with q_V_S would send for `r` (emulator side): Common group
// TimeStartup, Quaternion, AngularRate, Accel.
Message message_from(const ImuReading& r, const Quat& q_V_S);

// Every field of `m` as (name, value) pairs in wire order (groups, then field bits), one pair
// per scalar, for `orthosonar inspect --protocol vn100`. Names are those of the logger
// author's CSV where it has the field (MagX.. = IMU UncompMag, AccX.., GyroX.., Temp, Pres,
// Yaw, Pitch, Roll, DCM1..9, MagNED1..3, AccNED1..3); Common-group fields are prefixed
// "Common.". Floats with %.9g (float32 round-trips), doubles with %.17g, integers in decimal.
std::vector<std::pair<std::string, std::string>> describe(const Message& m);

}  // namespace orthosonar::hal::drivers::vn100
