// DVL protocols (dvl_protocols.hpp): the NMEA-like sentence framing the line protocols
// share, and the DVL frame conversions. The protocols: dvl_a50.cpp, dvl_prti.cpp,
// dvl_depth.cpp.
#include "hal/drivers/dvl_protocols.hpp"

#include <cassert>
#include <charconv>
#include <string>

#include "hal/drivers/dvl_detail.hpp"

namespace orthosonar::hal::drivers::dvl {

using namespace detail;

uint8_t nmea_checksum(std::string_view body) {
  uint8_t c = 0;
  for (char ch : body) c = static_cast<uint8_t>(c ^ static_cast<uint8_t>(ch));
  return c;
}

Result<std::string> nmea_body(std::string_view line) {
  line = trim(line);
  if (line.size() < 4 || line.front() != '$') return err("sentence must start with '$'");
  const size_t star = line.rfind('*');
  if (star == std::string_view::npos || star + 3 != line.size()) return err("missing *XX checksum");
  const std::string_view body = line.substr(1, star - 1);
  unsigned want = 0;
  const auto hex = line.substr(star + 1);
  const auto r = std::from_chars(hex.data(), hex.data() + 2, want, 16);
  if (r.ec != std::errc() || r.ptr != hex.data() + 2) return err("checksum is not hex");
  if (want != nmea_checksum(body)) return err("checksum mismatch");
  return std::string(body);
}

// ---- Frames ----------------------------------------------------------------------------------

Quat default_a50_mount() { return Quat(0.0, 1.0, 0.0, 0.0); }

DvlReading to_dvl_reading(const DvlVelocity& v, const Quat& q_V_D, Time stamp) {
  assert(v.frame == DvlFrame::kInstrument);
  DvlReading r;
  r.stamp = stamp;
  r.valid = v.valid;
  r.velocity_V_mps = q_V_D * v.velocity_D_mps;
  r.altitude_m = v.altitude_m;
  return r;
}

DvlVelocity velocity_from(const DvlReading& r, const Quat& q_V_D) {
  DvlVelocity v;
  v.valid = r.valid;
  v.velocity_D_mps = q_V_D.conjugate() * r.velocity_V_mps;
  v.altitude_m = r.altitude_m;
  return v;
}

}  // namespace orthosonar::hal::drivers::dvl
