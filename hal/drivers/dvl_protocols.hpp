#pragma once
// DVL and depth line protocols:
//  - Water Linked DVL A50 JSON over TCP 16171: one JSON object per line; "velocity" reports
//    carry vx, vy, vz (m/s, DVL frame: x forward, y right, z down), velocity_valid, altitude
//    (m, -1 when unknown) and time (ms since the last report). Other report types are skipped.
//  - Rowe SeaPilot $PRTI01 (NMEA-like, *XX checksum): start time (1/100 s), sample number,
//    temperature (1/100 C), bottom-track X, Y, Z velocity (mm/s, instrument frame, -99999 =
//    invalid), bottom-track depth (mm), water-mass X, Y, Z, water-mass depth, status (hex).
//  - Depth "$DEPTH,<metres>*XX" lines (our documented depth line protocol, docs/DRIVERS.md),
//    or an A50-style JSON {"type":"depth","depth":m}.
// DVL velocities are rotated into the vehicle frame V (REP-103) by the configured mounting
// rotation q_V_D.
#include <optional>
#include <string>
#include <string_view>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::hal::drivers::dvl {

inline constexpr uint16_t kA50Port = 16171;
inline constexpr int32_t kRoweInvalid = -99999;

struct DvlVelocity {  // in the DVL's own frame
  Vec3 velocity_D_mps = Vec3::Zero();
  bool valid = false;
  double altitude_m = -1.0;
};

// NMEA checksum: XOR of the characters between '$' and '*'.
uint8_t nmea_checksum(std::string_view body);
// Splits "$BODY*XX" after checking the checksum; returns BODY.
Result<std::string> nmea_body(std::string_view line);

// A50: nullopt for well-formed reports of other types; an Error for malformed JSON/fields.
Result<std::optional<DvlVelocity>> parse_a50_line(std::string_view line);
std::string encode_a50_velocity(const DvlVelocity& v, double time_ms);

Result<DvlVelocity> parse_prti01(std::string_view line);
std::string encode_prti01(const DvlVelocity& v, uint32_t sample, uint32_t start_time_cs);

Result<double> parse_depth_line(std::string_view line);  // $DEPTH or JSON depth
std::string encode_depth_line(double depth_m);

// Default mountings: A50 frame (FRD) to V is 180 degrees about x; PRTI01 instrument frame is
// taken as FLU (identity) unless configured.
Quat default_a50_mount();
DvlReading to_dvl_reading(const DvlVelocity& v, const Quat& q_V_D, Time stamp);
DvlVelocity velocity_from(const DvlReading& r, const Quat& q_V_D);

}  // namespace orthosonar::hal::drivers::dvl
