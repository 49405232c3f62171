// Rowe RTI binary ensembles (rti_ensemble.hpp): checksum, header, data sets, stream framing,
// conversion to DvlReading, encoding for the emulator, inspection.
#include "hal/drivers/rti_ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "hal/drivers/dvl_protocols.hpp"

namespace orthosonar::hal::drivers::rti {
namespace {

// ---- CRC-16/XMODEM, slicing by 8 ---------------------------------------------------------------
// kCrc[0] is the byte-wise table; kCrc[k][x] is the CRC of byte x followed by k zero bytes, so
// eight bytes b0..b7 (the register's two bytes folded into b0, b1) fold to
// XOR_i kCrc[7 - i][b_i]. Compared with the bit-wise definition in rti_ensemble_test.cpp.
using CrcTables = std::array<std::array<uint16_t, 256>, 8>;
constexpr CrcTables make_crc_tables() {
  CrcTables t{};
  for (unsigned x = 0; x < 256; ++x) {
    uint16_t c = static_cast<uint16_t>(x << 8);
    for (int i = 0; i < 8; ++i) c = (c & 0x8000) ? static_cast<uint16_t>((c << 1) ^ 0x1021) : static_cast<uint16_t>(c << 1);
    t[0][x] = c;
  }
  for (size_t k = 1; k < 8; ++k)
    for (unsigned x = 0; x < 256; ++x) {
      const uint16_t p = t[k - 1][x];
      t[k][x] = static_cast<uint16_t>((p << 8) ^ t[0][p >> 8]);
    }
  return t;
}
constexpr CrcTables kCrc = make_crc_tables();

uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 | static_cast<uint32_t>(p[2]) << 16 |
         static_cast<uint32_t>(p[3]) << 24;
}
int32_t lei32(const uint8_t* p) { return static_cast<int32_t>(le32(p)); }
float lef32(const uint8_t* p) {
  const uint32_t b = le32(p);
  float f;
  std::memcpy(&f, &b, sizeof f);
  return f;
}

Error err(const std::string& what) { return Error{"rti-ensemble: " + what}; }

std::string g9(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}
std::string hex4(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%04X", v);
  return b;
}
// Names and serial numbers as text: printable ASCII kept, anything else '?'.
std::string printable(const std::string& s) {
  std::string out = s;
  for (char& c : out)
    if (c < 0x20 || c > 0x7e) c = '?';
  return out;
}

bool good_velocity(float v) { return std::isfinite(v) && std::fabs(v) < kBadVelocity; }

// Days since 1970-01-01 of a proleptic Gregorian date, and back (H. Hinnant's algorithms).
int64_t days_from_civil(int64_t y, int64_t m, int64_t d) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t yoe = y - era * 400;
  const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}
void civil_from_days(int64_t z, int32_t& y, int32_t& m, int32_t& d) {
  z += 719468;
  const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const int64_t doe = z - era * 146097;
  const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const int64_t mp = (5 * doy + 2) / 153;
  d = static_cast<int32_t>(doy - (153 * mp + 2) / 5 + 1);
  m = static_cast<int32_t>(mp < 10 ? mp + 3 : mp - 9);
  y = static_cast<int32_t>(yoe + era * 400 + (m <= 2));
}

// ---- Data sets -------------------------------------------------------------------------------

Result<EnsembleData> decode_ensemble_data(const uint8_t* v, uint64_t count) {
  if (count < 13) return err("needs at least 13 values, has " + std::to_string(count));
  EnsembleData d;
  auto at = [&](size_t i) { return lei32(v + 4 * i); };
  d.ensemble_number = at(0);
  d.bins = at(1);
  d.beams = at(2);
  d.desired_pings = at(3);
  d.actual_pings = at(4);
  d.status = static_cast<uint32_t>(at(5));
  d.year = at(6);
  d.month = at(7);
  d.day = at(8);
  d.hour = at(9);
  d.minute = at(10);
  d.second = at(11);
  d.hundredths = at(12);
  if (count >= 21) {  // revision D: serial number, 32 characters in values 13..20
    d.serial.assign(reinterpret_cast<const char*>(v + 4 * 13), 32);
    while (!d.serial.empty() && d.serial.back() == '\0') d.serial.pop_back();
  }
  if (count >= 22) d.firmware = std::array<uint8_t, 4>{v[4 * 21], v[4 * 21 + 1], v[4 * 21 + 2], v[4 * 21 + 3]};
  if (count >= 23) d.subsystem_config = v[4 * 22 + 3];
  return d;
}

Result<BottomTrack> decode_bottom_track(const uint8_t* v, uint64_t count) {
  if (count < 14) return err("needs at least 14 values, has " + std::to_string(count));
  auto f = [&](size_t i) { return lef32(v + 4 * i); };
  BottomTrack bt;
  bt.first_ping_time_s = f(0);
  bt.last_ping_time_s = f(1);
  bt.heading_deg = f(2);
  bt.pitch_deg = f(3);
  bt.roll_deg = f(4);
  bt.water_temp_degc = f(5);
  bt.system_temp_degc = f(6);
  bt.salinity_ppt = f(7);
  bt.pressure_pa = f(8);
  bt.transducer_depth_m = f(9);
  bt.speed_of_sound_mps = f(10);
  const float status = f(11), beams = f(12);
  if (!(status >= 0.0f && status <= 4294967040.0f) || status != std::floor(status))
    return err("status " + g9(status) + " is not a 32-bit unsigned integer");
  if (!(beams >= 0.0f && beams <= static_cast<float>(kMaxBeams)) || beams != std::floor(beams))
    return err("number of beams " + g9(beams) + " is not an integer in 0.." + std::to_string(kMaxBeams));
  bt.status = static_cast<uint32_t>(status);
  bt.beams = static_cast<uint32_t>(beams);
  bt.actual_pings = f(13);
  if (count < 14 + 10 * uint64_t{bt.beams})
    return err(std::to_string(bt.beams) + " beams need " + std::to_string(14 + 10 * bt.beams) + " values, has " +
               std::to_string(count));
  size_t i = 14;
  for (BottomTrack::PerBeam* a : {&bt.range_m, &bt.snr_db, &bt.amplitude_db, &bt.correlation, &bt.beam_velocity_mps,
                                  &bt.beam_good, &bt.instrument_velocity_mps, &bt.instrument_good,
                                  &bt.earth_velocity_mps, &bt.earth_good})
    for (uint32_t b = 0; b < bt.beams; ++b) (*a)[b] = f(i++);
  return bt;
}

// The data sets of a checked ensemble (header and CRC already verified).
Result<Ensemble> decode_payload(std::span<const uint8_t> data, const Header& h) {
  Ensemble e;
  e.number = h.number;
  e.payload_bytes = h.payload_bytes;
  const uint8_t* p = data.data();
  size_t pos = kHeaderBytes;
  const size_t end = kHeaderBytes + h.payload_bytes;
  while (pos < end) {
    const std::string where = "ensemble " + std::to_string(h.number) + ", data set at byte " + std::to_string(pos);
    if (end - pos < kDataSetHeaderBytes)
      return err(where + ": a data set header needs 20 bytes, " + std::to_string(end - pos) + " left in the payload");
    DataSetInfo info;
    info.value_type = lei32(p + pos);
    info.elements = lei32(p + pos + 4);
    info.multiplier = lei32(p + pos + 8);
    const int32_t name_len = lei32(p + pos + 16);
    if (info.elements < 0 || info.multiplier < 0)
      return err(where + ": negative size (" + std::to_string(info.elements) + " x " + std::to_string(info.multiplier) + ")");
    if (name_len < 0 || name_len > 64) return err(where + ": name length " + std::to_string(name_len) + " (0..64)");
    const uint64_t value_bytes = info.value_type == kTypeByte ? 1 : 4;
    const uint64_t count = uint64_t(uint32_t(info.elements)) * uint64_t(uint32_t(info.multiplier));
    const uint64_t size = kDataSetHeaderBytes + uint64_t(uint32_t(name_len)) + count * value_bytes;
    const size_t name_at = pos + kDataSetHeaderBytes;
    info.name.assign(reinterpret_cast<const char*>(p + name_at), std::min<size_t>(size_t(name_len), end - name_at));
    while (!info.name.empty() && info.name.back() == '\0') info.name.pop_back();
    if (size > end - pos)
      return err(where + " ('" + printable(info.name) + "'): declares " + std::to_string(size) + " bytes, " +
                 std::to_string(end - pos) + " left in the payload");
    info.offset = static_cast<uint32_t>(pos);
    info.bytes = static_cast<uint32_t>(size);
    const uint8_t* values = p + name_at + name_len;
    const bool ours = info.name == kEnsembleDataName || info.name == kBottomTrackName;
    if (ours && value_bytes != 4) return err(where + " ('" + info.name + "'): value type 50 (bytes), expected 4-byte values");
    if (info.name == kEnsembleDataName) {
      auto d = decode_ensemble_data(values, count);
      if (!d) return err(where + " (" + info.name + ", ensemble data): " + d.error().message.substr(14));
      e.ensemble_data = std::move(*d);
    } else if (info.name == kBottomTrackName) {
      auto bt = decode_bottom_track(values, count);
      if (!bt) return err(where + " (" + info.name + ", bottom track): " + bt.error().message.substr(14));
      e.bottom_track = *bt;
    } else {
      ++e.unknown_data_sets;
    }
    info.decoded = ours;
    e.data_sets.push_back(std::move(info));
    pos += static_cast<size_t>(size);
  }
  return e;
}

void put_i32(Bytes& out, int32_t v) { ByteWriter(out).u32(static_cast<uint32_t>(v)); }
void put_f32(Bytes& out, float v) { ByteWriter(out).f32(v); }

}  // namespace

uint16_t crc16(std::span<const uint8_t> bytes) {
  uint16_t crc = 0;
  const uint8_t* p = bytes.data();
  size_t n = bytes.size();
  for (; n >= 8; n -= 8, p += 8) {
    crc = static_cast<uint16_t>(kCrc[7][p[0] ^ (crc >> 8)] ^ kCrc[6][p[1] ^ (crc & 0xff)] ^ kCrc[5][p[2]] ^
                                kCrc[4][p[3]] ^ kCrc[3][p[4]] ^ kCrc[2][p[5]] ^ kCrc[1][p[6]] ^ kCrc[0][p[7]]);
  }
  for (; n > 0; --n, ++p) crc = static_cast<uint16_t>((crc << 8) ^ kCrc[0][(crc >> 8) ^ *p]);
  return crc;
}

Result<int64_t> EnsembleData::unix_time_ns() const {
  static constexpr int kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  if (year < 1 || year > 9999 || month < 1 || month > 12 || day < 1 || day > kDays[month - 1] || hour < 0 ||
      hour > 23 || minute < 0 || minute > 59 || second < 0 || second > 60 || hundredths < 0 || hundredths > 99)
    return err("ensemble data: date and time " + std::to_string(year) + "-" + std::to_string(month) + "-" +
               std::to_string(day) + " " + std::to_string(hour) + ":" + std::to_string(minute) + ":" +
               std::to_string(second) + "." + std::to_string(hundredths) + " out of range");
  const int64_t s = days_from_civil(year, month, day) * 86400 + hour * 3600 + minute * 60 + second;
  return s * 1000000000 + int64_t{hundredths} * 10000000;
}

std::optional<Vec3> BottomTrack::instrument_xyz_mps() const {
  if (beams < 3) return std::nullopt;
  for (size_t i = 0; i < 3; ++i)
    if (!good_velocity(instrument_velocity_mps[i])) return std::nullopt;
  return Vec3(instrument_velocity_mps[0], instrument_velocity_mps[1], instrument_velocity_mps[2]);
}

std::optional<double> BottomTrack::mean_range_m() const {
  double sum = 0;
  int n = 0;
  for (uint32_t b = 0; b < beams; ++b)
    if (std::isfinite(range_m[b]) && range_m[b] > 0.0f) {
      sum += range_m[b];
      ++n;
    }
  if (n < 2) return std::nullopt;
  return sum / n;
}

std::optional<Header> parse_header(std::span<const uint8_t> d) {
  if (d.size() < kHeaderBytes) return std::nullopt;
  for (size_t i = 0; i < kSyncBytes; ++i)
    if (d[i] != kSyncByte) return std::nullopt;
  const uint32_t number = le32(&d[16]), not_number = le32(&d[20]);
  const uint32_t size = le32(&d[24]), not_size = le32(&d[28]);
  if (number != ~not_number || size != ~not_size || size > kMaxPayloadBytes) return std::nullopt;
  return Header{number, size};
}

Result<Ensemble> parse_ensemble(std::span<const uint8_t> data) {
  const auto h = parse_header(data);
  if (!h) return err("no valid header (16 x 0x80, ensemble number and payload size with their complements)");
  if (data.size() < h->total_bytes())
    return err("ensemble " + std::to_string(h->number) + " truncated: " + std::to_string(data.size()) + " of " +
               std::to_string(h->total_bytes()) + " bytes");
  const uint32_t want = le32(&data[kHeaderBytes + h->payload_bytes]);
  const uint16_t got = crc16(data.subspan(kHeaderBytes, h->payload_bytes));
  if (want != got) return err("ensemble " + std::to_string(h->number) + ": checksum " + hex4(want) + ", computed " + hex4(got));
  return decode_payload(data.first(h->total_bytes()), *h);
}

// ---- Encoding --------------------------------------------------------------------------------

Bytes encode_data_set(const std::string& name, int32_t value_type, int32_t elements, int32_t multiplier,
                      std::span<const uint8_t> values) {
  Bytes out;
  out.reserve(kDataSetHeaderBytes + 8 + values.size());
  for (int32_t v : {value_type, elements, multiplier, 0, 8}) put_i32(out, v);
  std::array<uint8_t, 8> n{};
  std::memcpy(n.data(), name.data(), std::min<size_t>(name.size(), 8));
  out.insert(out.end(), n.begin(), n.end());
  out.insert(out.end(), values.begin(), values.end());
  return out;
}

Bytes encode(const EnsembleData& d) {
  Bytes v;
  for (int32_t x : {d.ensemble_number, d.bins, d.beams, d.desired_pings, d.actual_pings, static_cast<int32_t>(d.status),
                    d.year, d.month, d.day, d.hour, d.minute, d.second, d.hundredths})
    put_i32(v, x);
  const bool rev_d = !d.serial.empty() || d.firmware || d.subsystem_config;
  if (rev_d) {
    std::array<uint8_t, 32> serial{};
    std::memcpy(serial.data(), d.serial.data(), std::min<size_t>(d.serial.size(), 32));
    v.insert(v.end(), serial.begin(), serial.end());
    const auto fw = d.firmware.value_or(std::array<uint8_t, 4>{});
    v.insert(v.end(), fw.begin(), fw.end());
    v.insert(v.end(), {0, 0, 0, d.subsystem_config.value_or(0)});
  }
  return encode_data_set(kEnsembleDataName, kTypeInt, rev_d ? 23 : 13, 1, v);
}

Bytes encode(const BottomTrack& bt) {
  const uint32_t beams = std::min<uint32_t>(bt.beams, kMaxBeams);
  Bytes v;
  for (float x : {bt.first_ping_time_s, bt.last_ping_time_s, bt.heading_deg, bt.pitch_deg, bt.roll_deg,
                  bt.water_temp_degc, bt.system_temp_degc, bt.salinity_ppt, bt.pressure_pa, bt.transducer_depth_m,
                  bt.speed_of_sound_mps, static_cast<float>(bt.status), static_cast<float>(beams), bt.actual_pings})
    put_f32(v, x);
  for (const BottomTrack::PerBeam* a : {&bt.range_m, &bt.snr_db, &bt.amplitude_db, &bt.correlation, &bt.beam_velocity_mps,
                                        &bt.beam_good, &bt.instrument_velocity_mps, &bt.instrument_good,
                                        &bt.earth_velocity_mps, &bt.earth_good})
    for (uint32_t b = 0; b < beams; ++b) put_f32(v, (*a)[b]);
  v.resize(v.size() + 5 * 4 * beams, 0);  // pulse-coherent SNR, amplitude, velocity, noise, correlation
  return encode_data_set(kBottomTrackName, kTypeFloat, static_cast<int32_t>(14 + 15 * beams), 1, v);
}

Bytes encode_ensemble(uint32_t number, std::span<const Bytes> data_sets) {
  size_t payload = 0;
  for (const auto& d : data_sets) payload += d.size();
  Bytes out;
  out.reserve(kHeaderBytes + payload + kChecksumBytes);
  out.resize(kSyncBytes, kSyncByte);
  ByteWriter w(out);
  w.u32(number);
  w.u32(~number);
  w.u32(static_cast<uint32_t>(payload));
  w.u32(~static_cast<uint32_t>(payload));
  for (const auto& d : data_sets) out.insert(out.end(), d.begin(), d.end());
  w.u32(crc16(std::span<const uint8_t>(out).subspan(kHeaderBytes)));
  return out;
}

Bytes encode_ensemble(const Ensemble& e) {
  std::vector<Bytes> sets;
  if (e.ensemble_data) sets.push_back(encode(*e.ensemble_data));
  if (e.bottom_track) sets.push_back(encode(*e.bottom_track));
  return encode_ensemble(e.number, sets);
}

// ---- Stream ----------------------------------------------------------------------------------

void StreamParser::push(std::span<const uint8_t> bytes) {
  if (start_ > 0) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(start_));
    consumed_ += start_;
    start_ = 0;
  }
  if (buf_.size() + bytes.size() > kMaxBuffered) {  // drop the oldest bytes (counted)
    const size_t drop = buf_.size() + bytes.size() - kMaxBuffered;
    const size_t old = std::min(drop, buf_.size());
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(old));
    bytes = bytes.subspan(drop - old);
    stats_.dropped_bytes += drop;
    consumed_ += drop;
  }
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void StreamParser::skip(size_t n) {
  start_ += n;
  stats_.skipped_bytes += n;
  // A failed ensemble whose whole span went by without another header: a bad checksum.
  if (failed_ && consumed_ + start_ >= failed_->end) {
    ++stats_.bad_checksum;
    last_error_ = failed_->what;
    failed_.reset();
  }
}

void StreamParser::resolve_failed(uint64_t header_at) {
  if (!failed_) return;
  // Another header inside the failed ensemble's span: it was cut short (partial).
  if (header_at < failed_->end) {
    ++stats_.partial;
    last_error_ = failed_->what + "; ensemble cut short by the header at byte " + std::to_string(header_at);
  } else {
    ++stats_.bad_checksum;
    last_error_ = failed_->what;
  }
  failed_.reset();
}

std::optional<Ensemble> StreamParser::pop() {
  for (;;) {
    // Find a run of 16 x 0x80.
    const uint8_t* base = buf_.data();
    const size_t size = buf_.size();
    const void* hit = start_ < size ? std::memchr(base + start_, kSyncByte, size - start_) : nullptr;
    if (hit == nullptr) {
      skip(size - start_);
      return std::nullopt;
    }
    const size_t at = static_cast<size_t>(static_cast<const uint8_t*>(hit) - base);
    if (at > start_) skip(at - start_);
    size_t run = 0;
    while (run < kSyncBytes && start_ + run < size && base[start_ + run] == kSyncByte) ++run;
    if (run < kSyncBytes) {
      if (start_ + run == size) return std::nullopt;  // the run may go on in the next bytes
      skip(run);  // no header can start inside a run cut by another byte
      continue;
    }
    if (size - start_ < kHeaderBytes) return std::nullopt;
    const std::span<const uint8_t> avail(base + start_, size - start_);
    const auto h = parse_header(avail);
    if (!h) {
      skip(1);  // not a header: its complements disagree (or the payload is too large)
      continue;
    }
    const uint64_t header_at = consumed_ + start_;
    resolve_failed(header_at);
    if (avail.size() < h->total_bytes()) {
      if (!finished_) return std::nullopt;
      // End of stream inside this ensemble: cut short. Decoding resumes at a later header, if any.
      size_t next = 1;
      while (next < avail.size() && !parse_header(avail.subspan(next))) ++next;
      if (next == avail.size() && end_counted_) return std::nullopt;
      ++stats_.partial;
      last_error_ = "rti-ensemble: ensemble " + std::to_string(h->number) + " at byte " + std::to_string(header_at) +
                    " cut short by the end of the stream: " + std::to_string(avail.size()) + " of " +
                    std::to_string(h->total_bytes()) + " bytes";
      if (next == avail.size()) {
        end_counted_ = true;  // it stays buffered: trailing bytes
        return std::nullopt;
      }
      skip(next);
      continue;
    }
    const auto ensemble = avail.first(h->total_bytes());
    const uint32_t want = le32(&ensemble[kHeaderBytes + h->payload_bytes]);
    const uint16_t got = crc16(ensemble.subspan(kHeaderBytes, h->payload_bytes));
    if (want != got) {
      failed_ = Failed{header_at + h->total_bytes(), "rti-ensemble: ensemble " + std::to_string(h->number) +
                                                         " at byte " + std::to_string(header_at) + ": checksum " +
                                                         hex4(want) + ", computed " + hex4(got)};
      skip(1);  // only the first sync byte: the next ensemble may start inside this one
      continue;
    }
    auto e = decode_payload(ensemble, *h);
    if (!e) {
      ++stats_.malformed;
      last_error_ = e.error().message + " (ensemble at byte " + std::to_string(header_at) + ")";
      skip(ensemble.size());
      continue;
    }
    start_ += ensemble.size();
    last_bytes_ = ensemble.size();
    ++stats_.ensembles;
    stats_.unknown_data_sets += e->unknown_data_sets;
    return std::move(*e);
  }
}

void StreamParser::finish() {
  finished_ = true;
  // After pop() drained, a pending failure has no header after it (pop() classifies it when it
  // meets one): nothing cut it short.
  if (failed_ && !parse_header(std::span<const uint8_t>(buf_.data() + start_, buf_.size() - start_))) {
    ++stats_.bad_checksum;
    last_error_ = failed_->what;
    failed_.reset();
  }
}

// ---- Conversion and inspection ---------------------------------------------------------------

std::optional<DvlReading> to_dvl_reading(const Ensemble& e, const Quat& q_V_D, Time stamp) {
  if (!e.bottom_track) return std::nullopt;
  const auto v = e.bottom_track->instrument_xyz_mps();
  dvl::DvlVelocity d;  // the instrument frame, as $PRTI01: the same conversion (dvl_protocols.cpp)
  d.frame = dvl::DvlFrame::kInstrument;
  d.valid = v.has_value();
  d.velocity_D_mps = v.value_or(Vec3::Zero());
  d.altitude_m = e.bottom_track->mean_range_m().value_or(-1.0);
  return dvl::to_dvl_reading(d, q_V_D, stamp);
}

Ensemble ensemble_from(const DvlReading& r, const Quat& q_V_D, uint32_t number, Time since_start) {
  const dvl::DvlVelocity v = dvl::velocity_from(r, q_V_D);
  Ensemble e;
  e.number = number;
  EnsembleData d;
  d.ensemble_number = static_cast<int32_t>(number);
  d.beams = 4;
  d.desired_pings = d.actual_pings = 1;
  const int64_t t0 = days_from_civil(2024, 1, 1) * 86400;
  const int64_t cs = std::max<int64_t>(0, since_start.ns() / 10000000);  // hundredths
  const int64_t secs = t0 + cs / 100;
  civil_from_days(secs / 86400, d.year, d.month, d.day);
  d.hour = static_cast<int32_t>(secs % 86400 / 3600);
  d.minute = static_cast<int32_t>(secs % 3600 / 60);
  d.second = static_cast<int32_t>(secs % 60);
  d.hundredths = static_cast<int32_t>(cs % 100);
  d.serial = "01000000000000000000000000000001";
  d.firmware = std::array<uint8_t, 4>{0, 0, 1, 'A'};
  d.subsystem_config = 0;
  e.ensemble_data = d;
  BottomTrack bt;
  bt.beams = 4;
  bt.actual_pings = 1;
  bt.speed_of_sound_mps = 1500.0f;
  bt.salinity_ppt = 35.0f;
  bt.status = v.valid ? 0 : 0x0008;  // searching
  for (size_t b = 0; b < 4; ++b) {
    bt.range_m[b] = v.altitude_m > 0 ? static_cast<float>(v.altitude_m) : 0.0f;
    bt.beam_velocity_mps[b] = bt.earth_velocity_mps[b] = kBadVelocity;
    bt.instrument_velocity_mps[b] = b < 3 && v.valid ? static_cast<float>(v.velocity_D_mps[static_cast<Eigen::Index>(b)])
                                    : v.valid        ? 0.0f
                                                     : kBadVelocity;
    bt.instrument_good[b] = v.valid ? 1.0f : 0.0f;
  }
  e.bottom_track = bt;
  return e;
}

std::vector<std::pair<std::string, std::string>> describe(const Ensemble& e) {
  std::vector<std::pair<std::string, std::string>> out;
  auto add = [&out](std::string k, std::string v) { out.emplace_back(std::move(k), std::move(v)); };
  add("ensemble_number", std::to_string(e.number));
  add("payload_bytes", std::to_string(e.payload_bytes));
  std::string names;
  for (const auto& d : e.data_sets) names += (names.empty() ? "" : ",") + printable(d.name);
  add("data_sets", names);
  add("unknown_data_sets", std::to_string(e.unknown_data_sets));
  if (const auto& d = e.ensemble_data) {
    add("ed_ensemble_number", std::to_string(d->ensemble_number));
    add("bins", std::to_string(d->bins));
    add("beams", std::to_string(d->beams));
    add("desired_pings", std::to_string(d->desired_pings));
    add("actual_pings", std::to_string(d->actual_pings));
    add("status", hex4(d->status));
    char t[96];
    std::snprintf(t, sizeof t, "%04d-%02d-%02dT%02d:%02d:%02d.%02d", d->year, d->month, d->day, d->hour, d->minute,
                  d->second, d->hundredths);
    add("time", t);
    if (!d->serial.empty()) add("serial", printable(d->serial));
    if (d->firmware) {
      const auto& f = *d->firmware;
      add("firmware", std::to_string(f[2]) + "." + std::to_string(f[1]) + "." + std::to_string(f[0]) + "-" +
                          printable(std::string(1, static_cast<char>(f[3]))));
    }
    if (d->subsystem_config) add("subsystem_config", std::to_string(*d->subsystem_config));
  }
  if (const auto& bt = e.bottom_track) {
    add("bt_first_ping_time_s", g9(bt->first_ping_time_s));
    add("bt_last_ping_time_s", g9(bt->last_ping_time_s));
    add("bt_heading_deg", g9(bt->heading_deg));
    add("bt_pitch_deg", g9(bt->pitch_deg));
    add("bt_roll_deg", g9(bt->roll_deg));
    add("bt_water_temp_degc", g9(bt->water_temp_degc));
    add("bt_system_temp_degc", g9(bt->system_temp_degc));
    add("bt_salinity_ppt", g9(bt->salinity_ppt));
    add("bt_pressure_pa", g9(bt->pressure_pa));
    add("bt_transducer_depth_m", g9(bt->transducer_depth_m));
    add("bt_speed_of_sound_mps", g9(bt->speed_of_sound_mps));
    add("bt_status", hex4(bt->status));
    add("bt_beams", std::to_string(bt->beams));
    add("bt_actual_pings", g9(bt->actual_pings));
    static const char* instr[] = {"x", "y", "z", "q"};
    static const char* earth[] = {"east", "north", "up", "error"};
    const std::pair<const char*, const BottomTrack::PerBeam*> arrays[] = {
        {"bt_range_m_", &bt->range_m},
        {"bt_snr_db_", &bt->snr_db},
        {"bt_amplitude_db_", &bt->amplitude_db},
        {"bt_correlation_", &bt->correlation},
        {"bt_beam_velocity_mps_", &bt->beam_velocity_mps},
        {"bt_beam_good_", &bt->beam_good},
        {"bt_instrument_velocity_mps_", &bt->instrument_velocity_mps},
        {"bt_instrument_good_", &bt->instrument_good},
        {"bt_earth_velocity_mps_", &bt->earth_velocity_mps},
        {"bt_earth_good_", &bt->earth_good}};
    for (size_t a = 0; a < std::size(arrays); ++a)
      for (uint32_t b = 0; b < bt->beams; ++b) {
        const bool named = b < 4 && (a == 6 || a == 8);
        add(arrays[a].first + (named ? std::string(a == 6 ? instr[b] : earth[b]) : std::to_string(b)),
            g9((*arrays[a].second)[b]));
      }
    add("bottom_track_valid", bt->instrument_xyz_mps() ? "true" : "false");
    add("altitude_m", g9(bt->mean_range_m().value_or(-1.0)));
  }
  return out;
}

}  // namespace orthosonar::hal::drivers::rti
