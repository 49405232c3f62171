// Rowe SeaPilot $PRTI01 / $PRTI02 sentences: parsing, encoding, inspection.
#include "hal/drivers/dvl_protocols.hpp"

#include <cstdio>
#include <iterator>
#include <string>

#include "hal/drivers/dvl_detail.hpp"

namespace orthosonar::hal::drivers::dvl {

using namespace detail;

namespace {

const char* prti_field_name(size_t i) {
  static const char* names[] = {"sentence id", "start time", "sample number", "temperature",
                                "bottom-track velocity 1", "bottom-track velocity 2", "bottom-track velocity 3",
                                "bottom-track depth", "water-mass velocity 1", "water-mass velocity 2",
                                "water-mass velocity 3", "water-mass depth", "status", "subsystem", "CEPO index"};
  return i < std::size(names) ? names[i] : "field";
}

}  // namespace

Result<PrtiReport> parse_prti(std::string_view line) {
  auto body = nmea_body(line);
  if (!body) return body.error();
  const auto f = split(*body, ',');
  PrtiReport r;
  if (f[0] == "PRTI01") {
    r.sentence = 1;
  } else if (f[0] == "PRTI02") {
    r.sentence = 2;
  } else {
    return err("expected $PRTI01 or $PRTI02, got $" + std::string(f[0]));
  }
  const std::string id = "$" + std::string(f[0]);
  if (f.size() < 13) return err(id + " needs 12 fields after the sentence id, got " + std::to_string(f.size() - 1));
  auto bad = [&](size_t i, const char* what) {
    return err(id + " field " + std::to_string(i) + " (" + prti_field_name(i) + ") " + what);
  };
  int64_t ints[3];
  for (size_t i = 1; i <= 3; ++i) {
    const auto v = to_int(f[i]);
    if (!v) return bad(i, "is not an integer");
    ints[i - 1] = *v;
  }
  r.start_time_cs = ints[0];
  r.sample = ints[1];
  r.temperature_cdegc = ints[2];
  // Three velocity components in mm/s; any -99999 invalidates the vector.
  auto velocity = [&](size_t first, bool allow_empty, std::optional<Vec3>& out) -> Status {
    if (allow_empty && f[first].empty() && f[first + 1].empty() && f[first + 2].empty()) return Status::Ok();
    Vec3 mps;
    bool valid = true;
    for (size_t i = 0; i < 3; ++i) {
      const auto mm = to_int(f[first + i]);
      if (!mm) return bad(first + i, "is not an integer");
      if (*mm == kRoweInvalid) {
        valid = false;
      } else if (*mm < -100000 || *mm > 100000) {
        return bad(first + i, "is out of range (|v| > 100 m/s)");
      }
      mps[static_cast<Eigen::Index>(i)] = static_cast<double>(*mm) / 1000.0;
    }
    if (valid) out = mps;
    return Status::Ok();
  };
  std::optional<Vec3> bt;
  if (auto s = velocity(4, false, bt); !s) return s.error();
  r.bottom_track.frame = r.sentence == 1 ? DvlFrame::kInstrument : DvlFrame::kEarthEnu;
  r.bottom_track.valid = bt.has_value();
  r.bottom_track.velocity_D_mps = bt.value_or(Vec3::Zero());
  const auto depth = to_int(f[7]);
  if (!depth) return bad(7, "is not an integer");
  r.bottom_track.altitude_m = *depth > 0 ? static_cast<double>(*depth) / 1000.0 : -1.0;
  if (auto s = velocity(8, true, r.water_mass_mps); !s) return s.error();
  if (!f[11].empty()) {
    const auto wm_depth = to_int(f[11]);
    if (!wm_depth) return bad(11, "is not an integer");
    r.water_mass_depth_m = static_cast<double>(*wm_depth) / 1000.0;
  }
  uint32_t status = 0;
  const auto st = std::from_chars(f[12].data(), f[12].data() + f[12].size(), status, 16);
  if (f[12].empty() || st.ec != std::errc() || st.ptr != f[12].data() + f[12].size()) return bad(12, "is not hex");
  r.status = status;
  for (size_t i : {size_t{13}, size_t{14}}) {
    if (i >= f.size() || f[i].empty()) continue;
    const auto v = to_int(f[i]);
    if (!v) return bad(i, "is not an integer");
    (i == 13 ? r.subsystem : r.cepo_index) = *v;
  }
  return r;
}

namespace {
Result<DvlVelocity> parse_prti_as(std::string_view line, int sentence) {
  auto r = parse_prti(line);
  if (!r) return r.error();
  if (r->sentence != sentence) {
    return err(sentence == 1 ? "expected $PRTI01 (instrument frame), got $PRTI02 (earth frame)"
                             : "expected $PRTI02 (earth frame), got $PRTI01 (instrument frame)");
  }
  return r->bottom_track;
}
}  // namespace

Result<DvlVelocity> parse_prti01(std::string_view line) { return parse_prti_as(line, 1); }
Result<DvlVelocity> parse_prti02(std::string_view line) { return parse_prti_as(line, 2); }

std::string encode_prti(const PrtiReport& r) {
  auto mm = [](double mps) { return std::to_string(static_cast<int64_t>(std::llround(mps * 1000.0))); };
  auto vec = [&](bool valid, const Vec3& v) {
    const std::string invalid = std::to_string(kRoweInvalid);
    if (!valid) return invalid + "," + invalid + "," + invalid;
    return mm(v.x()) + "," + mm(v.y()) + "," + mm(v.z());
  };
  const DvlVelocity& bt = r.bottom_track;
  std::string body = (r.sentence == 2 ? "PRTI02," : "PRTI01,") + std::to_string(r.start_time_cs) + "," +
                     std::to_string(r.sample) + "," + std::to_string(r.temperature_cdegc) + "," +
                     vec(bt.valid, bt.velocity_D_mps) + "," + (bt.altitude_m > 0 ? mm(bt.altitude_m) : "0") + ",";
  body += r.water_mass_mps ? vec(true, *r.water_mass_mps) : ",,";
  body += "," + (r.water_mass_depth_m ? mm(*r.water_mass_depth_m) : "") + ",";
  char status[16];
  std::snprintf(status, sizeof status, "%04X", r.status);
  body += status;
  if (r.subsystem || r.cepo_index) {
    body += "," + (r.subsystem ? std::to_string(*r.subsystem) : "") + "," +
            (r.cepo_index ? std::to_string(*r.cepo_index) : "");
  }
  return with_checksum(body);
}

std::string encode_prti01(const DvlVelocity& v, uint32_t sample, uint32_t start_time_cs) {
  PrtiReport r;
  r.sentence = 1;
  r.start_time_cs = start_time_cs;
  r.sample = sample;
  r.temperature_cdegc = 1464;
  r.bottom_track = v;
  r.status = 0x0004;
  return encode_prti(r);
}

FieldList describe(const PrtiReport& r) {
  const bool earth = r.bottom_track.frame == DvlFrame::kEarthEnu;
  const char* axes[3] = {earth ? "east" : "x", earth ? "north" : "y", earth ? "up" : "z"};
  FieldList out;
  out.emplace_back("sentence", r.sentence == 2 ? "PRTI02" : "PRTI01");
  out.emplace_back("frame", earth ? "earth (east, north, up)" : "instrument");
  out.emplace_back("start_time_s", g9(static_cast<double>(r.start_time_cs) / 100.0));
  out.emplace_back("sample", std::to_string(r.sample));
  out.emplace_back("temperature_degc", g9(static_cast<double>(r.temperature_cdegc) / 100.0));
  out.emplace_back("bottom_track_valid", boolean(r.bottom_track.valid));
  if (r.bottom_track.valid) {
    for (Eigen::Index i = 0; i < 3; ++i)
      out.emplace_back(std::string("bottom_track_") + axes[i] + "_mps", g9(r.bottom_track.velocity_D_mps[i]));
  }
  out.emplace_back("bottom_track_depth_m", g9(r.bottom_track.altitude_m));
  if (r.water_mass_mps) {
    for (Eigen::Index i = 0; i < 3; ++i)
      out.emplace_back(std::string("water_mass_") + axes[i] + "_mps", g9((*r.water_mass_mps)[i]));
  }
  if (r.water_mass_depth_m) out.emplace_back("water_mass_depth_m", g9(*r.water_mass_depth_m));
  char status[16];
  std::snprintf(status, sizeof status, "%04X", r.status);
  out.emplace_back("status", status);
  if (r.subsystem) out.emplace_back("subsystem", std::to_string(*r.subsystem));
  if (r.cepo_index) out.emplace_back("cepo_index", std::to_string(*r.cepo_index));
  return out;
}

}  // namespace orthosonar::hal::drivers::dvl
