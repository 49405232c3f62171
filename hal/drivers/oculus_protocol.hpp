#pragma once
// The Blueprint Subsea Oculus wire protocol (M750d, M1200d), from its public description:
// our own definitions, decoded field by field (little-endian, packed, no padding).
//
//   header (16 B)   u16 oculusId (0x4F53 "SO"), u16 srcDeviceId, u16 dstDeviceId, u16 msgId,
//                   u16 msgVersion, u32 payloadSize (bytes after the header), u16 spare
//   fire V1 (+37)   u8 masterMode, u8 pingRate, u8 networkSpeed, u8 gammaCorrection, u8 flags,
//                   f64 range (m or %), f64 gainPercent, f64 speedOfSound, f64 salinity  = 53 B
//   fire V2 (+36)   ... as V1, then u32 extFlags, u32 reserved[8]                        = 89 B
//   ping V1         fire V1, u32 pingId, u32 status, f64 frequency, f64 temperature,
//                   f64 pressure, f64 speedOfSoundUsed, u32 pingStartTime, u8 dataSize,
//                   f64 rangeResolution, u16 nRanges, u16 nBeams, u32 imageOffset,
//                   u32 imageSize, u32 messageSize                                     = 122 B
//   ping V2         fire V2, u32 pingId, u32 status, f64 frequency, temperature, pressure,
//                   heading, pitch, roll, speedOfSoundUsed, pingStartTime, u8 dataSize,
//                   f64 rangeResolution, u16 nRanges, u16 nBeams, u32 spare[4],
//                   u32 imageOffset, u32 imageSize, u32 messageSize                    = 202 B
//   then nBeams i16 bearings (1/100 degree), then at imageOffset nRanges rows of
//   [u32 gain if flags & kFlagSendGain] + nBeams pixels of (dataSize + 1) bytes.
// Status (UDP 52102, our layout of the public fields, see docs/DRIVERS.md): header, u32 deviceId,
//   u16 deviceType, u16 partNumber, u32 status, u32 versions[6], u32 ipAddr, u32 ipMask,
//   u32 connectedIpAddr, u8 mac[6], f64 temperature[8], f64 pressure                   = 142 B
#include <cstdint>
#include <span>
#include <variant>
#include <vector>

#include "core/result.hpp"
#include "hal/drivers/bytes.hpp"

namespace orthosonar::hal::drivers::oculus {

inline constexpr uint16_t kOculusId = 0x4F53;
inline constexpr uint16_t kTcpPort = 52100;
inline constexpr uint16_t kStatusUdpPort = 52102;
inline constexpr size_t kHeaderSize = 16;
inline constexpr size_t kFireV1Size = 53;
inline constexpr size_t kFireV2Size = 89;
inline constexpr size_t kPingV1Size = 122;
inline constexpr size_t kPingV2Size = 202;
inline constexpr size_t kStatusSize = 142;
inline constexpr uint32_t kMaxPayload = 16u << 20;  // larger payload sizes are garbage

enum MessageId : uint16_t {
  kMsgStatus = 0x0001,  // status broadcast (identified by the UDP port on real devices)
  kMsgSimpleFire = 0x15,
  kMsgPingResult = 0x22,
  kMsgSimplePingResult = 0x23,
  kMsgUserConfig = 0x55,
  kMsgDummy = 0xFF,
};

// Fire-message flag bits.
inline constexpr uint8_t kFlagRangeAsMeters = 0x01;
inline constexpr uint8_t kFlagData16Bit = 0x02;
inline constexpr uint8_t kFlagSendGain = 0x04;
inline constexpr uint8_t kFlagSimpleReturn = 0x08;
inline constexpr uint8_t kFlagGainAssist = 0x10;
inline constexpr uint8_t kFlag512Beams = 0x40;

inline constexpr uint8_t kModeLowFrequency = 1;   // wide aperture (130 degrees)
inline constexpr uint8_t kModeHighFrequency = 2;  // narrow aperture

struct Header {
  uint16_t oculus_id = kOculusId;
  uint16_t src_device_id = 0;
  uint16_t dst_device_id = 0;
  uint16_t msg_id = 0;
  uint16_t msg_version = 0;
  uint32_t payload_size = 0;
  uint16_t spare = 0;
  size_t message_bytes() const { return kHeaderSize + payload_size; }
  friend bool operator==(const Header&, const Header&) = default;
};

// A SimpleFire configuration (what the host sends; echoed at the start of every ping).
struct FireConfig {
  uint8_t master_mode = kModeLowFrequency;
  uint8_t ping_rate = 0;        // 0 normal (10 Hz max) ... 5 standby
  uint8_t network_speed = 0xFF;
  uint8_t gamma = 127;          // 127 = gamma 0.5; 0 or 255 = 1.0
  uint8_t flags = kFlagRangeAsMeters | kFlagSimpleReturn | kFlag512Beams;
  double range = 30.0;          // metres when kFlagRangeAsMeters, else percent
  double gain_percent = 50.0;
  double speed_of_sound_mps = 0.0;  // 0: the device computes it from salinity
  double salinity_ppt = 0.0;
  uint32_t ext_flags = 0;       // V2 only
  friend bool operator==(const FireConfig&, const FireConfig&) = default;
};

struct PingResult {
  Header header;
  int version = 1;  // 1 or 2 (header.msgVersion 2 selects V2)
  FireConfig fire;
  uint32_t ping_id = 0;
  uint32_t status = 0;
  double frequency_hz = 0.0;
  double temperature_c = 0.0;
  double pressure_bar = 0.0;
  double heading_deg = 0.0, pitch_deg = 0.0, roll_deg = 0.0;  // V2 only
  double speed_of_sound_used_mps = 0.0;
  double ping_start_time = 0.0;  // V1 sends a u32, V2 a f64
  uint8_t data_size = 0;         // 0: 8-bit, 1: 16-bit, 2: 24-bit, 3: 32-bit
  double range_resolution_m = 0.0;
  uint16_t n_ranges = 0;
  uint16_t n_beams = 0;
  uint32_t image_offset = 0;
  uint32_t image_size = 0;
  uint32_t message_size = 0;
  std::vector<int16_t> bearings_centideg;  // n_beams
  std::vector<uint32_t> row_gains;         // n_ranges when flags & kFlagSendGain, else empty
  Bytes image;                             // n_ranges * n_beams * bytes_per_pixel(), gains removed

  int bytes_per_pixel() const { return data_size + 1; }
  bool has_gain() const { return (fire.flags & kFlagSendGain) != 0; }
};

struct StatusMessage {
  Header header;
  uint32_t device_id = 0;
  uint16_t device_type = 1;  // imaging sonar
  uint16_t part_number = 0;
  uint32_t status = 0;
  uint32_t ip_addr = 0;
  uint32_t ip_mask = 0;
  uint32_t connected_ip_addr = 0;
  double temperature0_c = 0.0;
  double pressure_bar = 0.0;
};

struct FireMessage {
  Header header;
  FireConfig config;
};

struct OtherMessage {
  Header header;
};

using Message = std::variant<PingResult, StatusMessage, FireMessage, OtherMessage>;

// Decodes the 16-byte header at the start of `data` (checks the id and payload bound).
Result<Header> parse_header(std::span<const uint8_t> data);
// Decodes one complete message (header + payload; `data` may be longer, the rest is ignored).
// Every size is checked: truncated or inconsistent messages are errors, never reads past the end.
Result<Message> parse_message(std::span<const uint8_t> data);
Result<PingResult> parse_ping_result(std::span<const uint8_t> data);
Result<StatusMessage> parse_status(std::span<const uint8_t> data);

// Encoders (the host's fire message; the emulator's pings and status).
Bytes encode_fire(const FireConfig& config, int version, uint16_t src_device_id, uint16_t dst_device_id);
// Encodes a ping; header sizes, offsets and image sizes are computed from the content.
Bytes encode_ping_result(const PingResult& ping);
Bytes encode_status(const StatusMessage& status);

}  // namespace orthosonar::hal::drivers::oculus
