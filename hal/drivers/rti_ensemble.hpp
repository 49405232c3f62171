#pragma once
// Rowe Technologies (RTI) binary ensembles, the "RTB" format Rowe DVLs and ADCPs stream besides
// their $PRTI01/$PRTI02 sentences (docs/DRIVERS.md, "Rowe RTI binary ensembles", says where
// each detail below was confirmed). All integers and floats little-endian.
//
//   ensemble  = header (32 bytes) | payload (payload_size bytes) | checksum (4 bytes)
//   header    = 16 x 0x80 | ensemble number (int32) | ~ensemble number | payload size (int32)
//               | ~payload size                        (~ = bitwise complement)
//   checksum  = CRC-16/XMODEM (poly 0x1021, init 0, no reflection, no final XOR) of the payload
//               alone, in the low 16 bits of a uint32 (its top two bytes are 0)
//   payload   = data sets, back to back
//   data set  = value type (int32: 10 float, 20 int, 50 byte) | number of elements (bins)
//               | element multiplier (beams) | image (unused) | name length (int32)
//               | name (name-length bytes, "E000010\0") | elements x multiplier values
//               (1 byte each for type 50, 4 bytes otherwise)
//
// Decoded data sets: E000008 (ensemble data: number, bins, beams, pings, status, date and
// time, serial number, firmware) and E000010 (bottom track: ping times, attitude, temperatures,
// status, per-beam range, SNR, amplitude, correlation, beam / instrument / earth velocities and
// their good-ping counts). Every other data set (profiles E000001-E000007, ancillary E000009,
// NMEA E000011, ...) is skipped by its declared size and counted. 88.888 marks a bad velocity,
// 0 a bad range.
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

namespace orthosonar::hal::drivers::rti {

inline constexpr size_t kSyncBytes = 16;
inline constexpr uint8_t kSyncByte = 0x80;
inline constexpr size_t kHeaderBytes = 32;
inline constexpr size_t kChecksumBytes = 4;
inline constexpr size_t kDataSetHeaderBytes = 20;  // five int32 before the name
// Largest payload accepted; a header declaring more is rejected (no RTI ensemble comes close:
// 200 bins x 4 beams x 7 profile data sets is ~23 KB).
inline constexpr uint32_t kMaxPayloadBytes = 256 * 1024;
inline constexpr size_t kMaxBeams = 16;
inline constexpr float kBadVelocity = 88.888f;
inline constexpr int32_t kTypeFloat = 10, kTypeInt = 20, kTypeByte = 50;
inline constexpr char kEnsembleDataName[] = "E000008";
inline constexpr char kAncillaryName[] = "E000009";
inline constexpr char kBottomTrackName[] = "E000010";

// CRC-16/XMODEM as Rowe computes the ensemble checksum (table-driven, 8 bytes per step).
uint16_t crc16(std::span<const uint8_t> bytes);

// E000008: integers describing the ensemble (13 values; firmware revision D on adds the
// serial number and the firmware version, 23 values).
struct EnsembleData {
  int32_t ensemble_number = 0, bins = 0, beams = 0, desired_pings = 0, actual_pings = 0;
  uint32_t status = 0;
  int32_t year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0, hundredths = 0;
  std::string serial;  // 32 characters when present (revision D), else empty
  std::optional<std::array<uint8_t, 4>> firmware;  // revision, minor, major, subsystem code (ASCII)
  std::optional<uint8_t> subsystem_config;
  // The ensemble's date and time as Unix nanoseconds (UTC as the instrument keeps it); an error
  // when a field is out of its calendar range.
  Result<int64_t> unix_time_ns() const;
  friend bool operator==(const EnsembleData&, const EnsembleData&) = default;
};

// E000010: bottom track, 14 scalars then per-beam arrays (10 of them; newer firmware appends 5
// pulse-coherent arrays, which are not decoded).
struct BottomTrack {
  float first_ping_time_s = 0, last_ping_time_s = 0;
  float heading_deg = 0, pitch_deg = 0, roll_deg = 0;
  float water_temp_degc = 0, system_temp_degc = 0, salinity_ppt = 0, pressure_pa = 0;
  float transducer_depth_m = 0, speed_of_sound_mps = 0;
  uint32_t status = 0;  // sent as a float; bits: 0x0001 long lag, 0x0002 3-beam solution, 0x0004
                        // hold, 0x0008 searching, 0x0020 coast, 0x0040 proof, 0x0080 low gain, ...
  uint32_t beams = 0;   // sent as a float; 1..kMaxBeams
  float actual_pings = 0;
  using PerBeam = std::array<float, kMaxBeams>;  // entries [0, beams) are meaningful
  PerBeam range_m{}, snr_db{}, amplitude_db{}, correlation{};
  PerBeam beam_velocity_mps{}, beam_good{};
  PerBeam instrument_velocity_mps{}, instrument_good{};  // X, Y, Z, error (Q)
  PerBeam earth_velocity_mps{}, earth_good{};            // east, north, up, error
  // Instrument X, Y, Z when there are at least 3 beams and none is bad (88.888, not finite or
  // faster than 100 m/s).
  std::optional<Vec3> instrument_xyz_mps() const;
  // Mean of the good ranges (> 0 and finite); at least two are needed, as Rowe's RTI library
  // (BottomTrackDataSet.GetAverageRange) requires; nullopt otherwise.
  std::optional<double> mean_range_m() const;
  friend bool operator==(const BottomTrack&, const BottomTrack&) = default;
};

// One data set as it appeared in the payload (decoded or skipped).
struct DataSetInfo {
  std::string name;  // without the trailing NULs
  int32_t value_type = 0, elements = 0, multiplier = 0;
  uint32_t offset = 0;  // from the start of the ensemble
  uint32_t bytes = 0;   // header, name and values
  bool decoded = false;
  friend bool operator==(const DataSetInfo&, const DataSetInfo&) = default;
};

struct Ensemble {
  uint32_t number = 0;  // from the header
  uint32_t payload_bytes = 0;
  std::optional<EnsembleData> ensemble_data;
  std::optional<BottomTrack> bottom_track;
  std::vector<DataSetInfo> data_sets;  // every data set, in payload order
  uint32_t unknown_data_sets = 0;      // skipped by their declared size
  friend bool operator==(const Ensemble&, const Ensemble&) = default;
};

// Header check of the 32 bytes at `data` (sync run, complements, payload bound). nullopt: not
// an ensemble header.
struct Header {
  uint32_t number = 0, payload_bytes = 0;
  size_t total_bytes() const { return kHeaderBytes + payload_bytes + kChecksumBytes; }
};
std::optional<Header> parse_header(std::span<const uint8_t> data);

// One complete ensemble (header to checksum). Errors name the byte offset and the data set.
Result<Ensemble> parse_ensemble(std::span<const uint8_t> data);

// ---- Encoding (emulator, tests) ----------------------------------------------------------------
// A data set with its header; `values` must hold elements x multiplier values of the type's size.
Bytes encode_data_set(const std::string& name, int32_t value_type, int32_t elements, int32_t multiplier,
                      std::span<const uint8_t> values);
Bytes encode(const EnsembleData& d);  // 23 int32 values (revision D layout)
Bytes encode(const BottomTrack& bt);  // 14 + 15 x beams floats (pulse-coherent arrays 0)
// Header, the data sets as given, checksum.
Bytes encode_ensemble(uint32_t number, std::span<const Bytes> data_sets);
// The ensemble data set (when present), then bottom track (when present).
Bytes encode_ensemble(const Ensemble& e);

// ---- Stream ----------------------------------------------------------------------------------
struct StreamStats {
  uint64_t ensembles = 0;          // good checksum and data sets, returned by pop()
  uint64_t bad_checksum = 0;       // complete ensembles whose CRC failed
  uint64_t partial = 0;            // ensembles cut short: another header inside their declared
                                   // span, or the stream ended (finish()) inside one
  uint64_t malformed = 0;          // good CRC but data sets overrunning the payload or too short
  uint64_t unknown_data_sets = 0;  // data sets skipped by their declared size (in good ensembles)
  uint64_t skipped_bytes = 0;      // garbage before a header, rejected headers and ensembles
  uint64_t dropped_bytes = 0;      // discarded unread because the buffer was full
};

// Byte-stream framing with resynchronisation on the 16 x 0x80 header. A header whose
// complements disagree is not a header (one byte skipped). A complete ensemble whose CRC fails
// is "partial" when another valid header starts inside it (the stream resumes there: a device
// restarted mid-ensemble), else "bad checksum" (all its bytes skipped). Every byte pushed ends
// up in an ensemble, skipped, dropped or still buffered. Not thread-safe.
class StreamParser {
 public:
  static constexpr size_t kMaxBuffered = 2 * (kMaxPayloadBytes + kHeaderBytes + kChecksumBytes);
  void push(std::span<const uint8_t> bytes);
  // The next good ensemble, or nullopt when more bytes are needed. Call until nullopt.
  std::optional<Ensemble> pop();
  // End of stream; pop() again afterwards. An ensemble the stream ends inside is partial:
  // decoding resumes at a later header in the buffer, else its bytes stay buffered (trailing).
  void finish();
  const StreamStats& stats() const { return stats_; }
  // After finish(): whether the stream ended inside an ensemble (one of the partial ones).
  bool ended_inside() const { return end_counted_; }
  size_t buffered() const { return buf_.size() - start_; }
  size_t last_ensemble_bytes() const { return last_bytes_; }
  const std::string& last_error() const { return last_error_; }

 private:
  struct Failed {
    uint64_t end = 0;  // stream offset just past the failed ensemble's declared span
    std::string what;
  };
  void skip(size_t n);
  void resolve_failed(uint64_t header_at);
  Bytes buf_;
  size_t start_ = 0;
  uint64_t consumed_ = 0;  // stream offset of buf_[0]
  size_t last_bytes_ = 0;
  bool finished_ = false, end_counted_ = false;
  std::optional<Failed> failed_;  // a CRC failure not yet classified (partial or bad checksum)
  StreamStats stats_;
  std::string last_error_;
};

// ---- Conversion ------------------------------------------------------------------------------
// The DVL reading of an ensemble with a bottom-track data set (nullopt without one): the
// instrument-frame velocity X, Y, Z rotated into V by the mounting q_V_D (as $PRTI01, which
// carries the same instrument velocity in mm/s), valid when the three are good, altitude the
// mean good range (<= 0 unknown). Earth-frame and beam velocities need attitude or beam
// geometry and are not used.
std::optional<DvlReading> to_dvl_reading(const Ensemble& e, const Quat& q_V_D, Time stamp);
// The ensemble a Rowe DVL mounted with q_V_D sends for `r` (emulator side): ensemble data with
// `number` and the time `since_start` after 2024-01-01T00:00:00, a 4-beam bottom track with
// the instrument velocity (88.888 when invalid), every range = altitude (0 when unknown),
// earth and beam velocities bad.
Ensemble ensemble_from(const DvlReading& r, const Quat& q_V_D, uint32_t number, Time since_start);

// Every decoded field as (name, value text) in wire order, numbers at %.9g, for
// `orthosonar inspect --protocol rti-ensemble`.
std::vector<std::pair<std::string, std::string>> describe(const Ensemble& e);

}  // namespace orthosonar::hal::drivers::rti
