#pragma once
// DVL and depth line protocols (docs/DRIVERS.md, "DVL and depth", lists every accepted variant
// with an example line and the documentation it comes from):
//  - Water Linked DVL A50 JSON over TCP 16171, one JSON object per line, firmware formats
//    json_v1, json_v2 and json_v3.x: velocity(-and-transducer) reports (vx, vy, vz in m/s in the
//    DVL frame: x forward, y right, z down), dead-reckoning reports ("position_local", json_v2
//    on) and other types (command responses), which are skipped.
//  - Rowe SeaPilot $PRTI01 (bottom track in the instrument frame) and $PRTI02 (the same layout
//    with earth-frame east/north/up velocities), NMEA-like with a *XX checksum.
//  - Depth "$DEPTH,<metres>*XX" lines (our documented depth line protocol) or an A50-style
//    JSON {"type":"depth","depth":m}.
// Instrument-frame DVL velocities are rotated into the vehicle frame V (REP-103) by the
// configured mounting rotation q_V_D. Earth-frame ($PRTI02) velocities need the vehicle's
// attitude instead; the frame is part of the decoded data so a consumer cannot mix them up.
// Every parser returns a value or an Error naming the field at fault. Line lengths are bounded
// by the LineFramer the drivers read through; no parser keeps more than the last report.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/events.hpp"
#include "core/result.hpp"

namespace orthosonar::hal::drivers::dvl {

inline constexpr uint16_t kA50Port = 16171;
inline constexpr int32_t kRoweInvalid = -99999;

// The frame a DVL velocity is expressed in.
enum class DvlFrame {
  kInstrument,  // the DVL's own axes (A50: x forward, y right, z down; Rowe: instrument X, Y, Z)
  kEarthEnu,    // east, north, up ($PRTI02): needs heading/attitude, not the mounting rotation
};

struct DvlVelocity {
  Vec3 velocity_D_mps = Vec3::Zero();  // in `frame` (D = the DVL's own frame when kInstrument)
  bool valid = false;
  double altitude_m = -1.0;  // distance to the bottom; -1 when unknown
  DvlFrame frame = DvlFrame::kInstrument;
  friend bool operator==(const DvlVelocity&, const DvlVelocity&) = default;
};

// NMEA checksum: XOR of the characters between '$' and '*'.
uint8_t nmea_checksum(std::string_view body);
// Splits "$BODY*XX" after checking the checksum; returns BODY.
Result<std::string> nmea_body(std::string_view line);

// ---- Water Linked A50 JSON -------------------------------------------------------------------
// Required keys per report and format (a missing one or a wrong type is an Error naming it;
// unknown keys are ignored, so newer minor versions parse):
//   velocity, all formats   vx, vy, vz (number), velocity_valid (bool)
//   velocity, json_v1       "type" may be absent (then the line must carry "vx")
//   velocity, json_v2       "type" required
//   velocity, json_v3.x     "type" and time_of_validity (integer, Unix µs) required
//   position_local (v2, v3) ts, x, y, z, std (json_v2 docs: "pos_std"), roll, pitch, yaw
//                           (json_v2 docs example: "jaw"), status
// Optional keys are type-checked when present: time, fom, altitude, status, covariance (3x3),
// transducers, time_of_transmission, tracking_mode, format. A missing "format" is inferred
// (velocity: json_v3 with time_of_validity, else json_v1; position_local: json_v2); a format
// other than json_v1, json_v2, json_v3[.minor] is an error.
struct A50Transducer {
  int64_t id = 0;
  double velocity_mps = 0, distance_m = 0, rssi_dbm = 0, nsd_dbm = 0;
  bool beam_valid = false;
  friend bool operator==(const A50Transducer&, const A50Transducer&) = default;
};

struct A50Velocity {
  std::string format;    // as sent ("json_v1", "json_v3.1"); empty when absent
  int format_major = 1;  // 1, 2 or 3 (inferred when "format" is absent)
  std::string type;      // "velocity", "velocity_water" (json_v3.2); empty when absent (json_v1)
  DvlVelocity velocity;  // vx, vy, vz (instrument frame), velocity_valid, altitude (-1 if absent)
  std::optional<double> time_ms;  // milliseconds since the previous velocity report
  std::optional<double> fom_mps;  // figure of merit
  std::optional<int64_t> status;  // bit 0: high temperature
  std::optional<Eigen::Matrix3d> covariance_m2ps2;
  std::optional<int64_t> time_of_validity_us;     // centre of ping, Unix µs (json_v3)
  std::optional<int64_t> time_of_transmission_us;  // just before sending, Unix µs (json_v3)
  std::optional<std::string> tracking_mode;        // "bottom" or "water" (json_v3.2)
  std::vector<A50Transducer> transducers;
  // Velocity over the ground (bottom lock), as opposed to water tracking.
  bool bottom_tracked() const { return type != "velocity_water" && tracking_mode != "water"; }
  friend bool operator==(const A50Velocity&, const A50Velocity&) = default;
};

// Position and orientation by the A50's own dead reckoning, in the frame of the DVL's axes at
// the last reset (x, y horizontal, z down).
struct A50DeadReckoning {
  std::string format;    // "json_v2", "json_v3.1", ...; empty when absent
  int format_major = 2;
  double ts = 0;         // as sent: Unix seconds (json_v3 docs) or ms since reset (json_v2 docs)
  Vec3 position_m = Vec3::Zero();  // x, y, z (z down)
  double std_m = 0;                // position standard deviation (figure of merit)
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
  int64_t status = 0;              // 0: valid, otherwise not valid
  friend bool operator==(const A50DeadReckoning&, const A50DeadReckoning&) = default;
};

struct A50Other {  // a well-formed object of another type ("response", ...): skipped
  std::string type;
  friend bool operator==(const A50Other&, const A50Other&) = default;
};

using A50Report = std::variant<A50Velocity, A50DeadReckoning>;
using A50Decoded = std::variant<A50Velocity, A50DeadReckoning, A50Other>;

// One line, no state.
Result<A50Decoded> decode_a50(std::string_view line);

// A stream of A50 lines: decodes, counts and drops duplicate reports. A report is a duplicate
// of the last accepted report of the same kind (velocity or dead reckoning) when
//   - velocity with time_of_validity (json_v3): the same time_of_validity;
//   - velocity without it (json_v1, json_v2): the same line bytes (leading/trailing blanks and
//     CR/LF ignored), which no two real reports share ("time" changes with every ping);
//   - dead reckoning: the same "ts".
// Only the last key of each kind is kept (bounded state). Malformed lines and other types do
// not change it. Not thread-safe: one parser per stream.
class A50Parser {
 public:
  struct Counters {
    uint64_t velocity = 0;        // accepted velocity reports
    uint64_t dead_reckoning = 0;  // accepted dead-reckoning reports
    uint64_t duplicates = 0;      // dropped duplicates (either kind)
    uint64_t other = 0;           // responses and other report types
    uint64_t malformed = 0;       // not JSON, or a report with missing/mistyped keys
  };
  // A report; nullopt for a duplicate or another report type; an Error for a malformed line.
  Result<std::optional<A50Report>> parse(std::string_view line);
  const Counters& counters() const { return counters_; }

 private:
  std::string last_velocity_key_;             // "tov:<µs>" or "line:<trimmed line>"
  std::optional<double> last_dead_reckoning_ts_;
  Counters counters_;
};

// Bottom-tracked velocity reports only; nullopt for every other well-formed line (dead
// reckoning, water tracking, responses); no duplicate detection.
Result<std::optional<DvlVelocity>> parse_a50_line(std::string_view line);
// Lossless encoders (numbers at %.17g) writing the keys a report holds, in the device's order.
std::string encode_a50(const A50Velocity& r);
std::string encode_a50(const A50DeadReckoning& r);
// A velocity line: json_v3.1 with time_of_validity = time_of_transmission when given, else a
// json_v2 line (which the duplicate rule compares by content).
std::string encode_a50_velocity(const DvlVelocity& v, double time_ms,
                                std::optional<int64_t> time_of_validity_us = std::nullopt);

// ---- Rowe SeaPilot $PRTI01 / $PRTI02 ---------------------------------------------------------
// $PRTIxx,<start time 1/100 s>,<sample>,<temperature 1/100 °C>,<BT 1>,<BT 2>,<BT 3 mm/s>,
//   <BT depth mm>,<WM 1>,<WM 2>,<WM 3 mm/s>,<WM depth mm>,<status hex>[,<subsystem>,<CEPO>]*XX
// PRTI01: components X, Y, Z of the instrument frame; PRTI02: east, north, up. -99999 marks an
// invalid velocity; BT depth 0 = no bottom; water-mass fields may be empty. Newer firmware
// appends the subsystem and its CEPO index; fields after those are ignored.
struct PrtiReport {
  int sentence = 1;  // 1 ($PRTI01) or 2 ($PRTI02)
  int64_t start_time_cs = 0;
  int64_t sample = 0;
  int64_t temperature_cdegc = 0;
  DvlVelocity bottom_track;  // frame kInstrument (PRTI01) or kEarthEnu (PRTI02)
  std::optional<Vec3> water_mass_mps;        // same frame; absent when empty or invalid
  std::optional<double> water_mass_depth_m;  // absent when empty
  uint32_t status = 0;
  std::optional<int64_t> subsystem, cepo_index;
  friend bool operator==(const PrtiReport&, const PrtiReport&) = default;
};

Result<PrtiReport> parse_prti(std::string_view line);  // either sentence, by its id
// Bottom-track velocity of one sentence; the other sentence id is an error (PRTI01 yields
// kInstrument, PRTI02 kEarthEnu).
Result<DvlVelocity> parse_prti01(std::string_view line);
Result<DvlVelocity> parse_prti02(std::string_view line);
std::string encode_prti(const PrtiReport& r);  // velocities rounded to mm/s, depths to mm
std::string encode_prti01(const DvlVelocity& v, uint32_t sample, uint32_t start_time_cs);

// ---- Depth -----------------------------------------------------------------------------------
struct DepthLine {
  double depth_m = 0;
  bool json = false;  // {"type":"depth",...} rather than $DEPTH
};
Result<DepthLine> parse_depth(std::string_view line);
Result<double> parse_depth_line(std::string_view line);  // parse_depth(...).depth_m
std::string encode_depth_line(double depth_m);

// ---- Inspection ------------------------------------------------------------------------------
// Every decoded field as (name, value text) in wire order, numbers at %.9g, for
// `orthosonar inspect --protocol a50|prti|depth`. A50 names are the JSON keys.
using FieldList = std::vector<std::pair<std::string, std::string>>;
FieldList describe(const A50Velocity& r);
FieldList describe(const A50DeadReckoning& r);
FieldList describe(const A50Other& r);
FieldList describe(const A50Decoded& r);
FieldList describe(const A50Report& r);
FieldList describe(const PrtiReport& r);
FieldList describe(const DepthLine& r);

// ---- Frames ----------------------------------------------------------------------------------
// Default mountings: A50 frame (FRD) to V is 180 degrees about x; PRTI01 instrument frame is
// taken as FLU (identity) unless configured.
Quat default_a50_mount();
// Requires v.frame == kInstrument (earth-frame velocities are not rotated by a mounting).
DvlReading to_dvl_reading(const DvlVelocity& v, const Quat& q_V_D, Time stamp);
DvlVelocity velocity_from(const DvlReading& r, const Quat& q_V_D);

}  // namespace orthosonar::hal::drivers::dvl
