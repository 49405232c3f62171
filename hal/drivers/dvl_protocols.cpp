#include "hal/drivers/dvl_protocols.hpp"

#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

namespace orthosonar::hal::drivers::dvl {
namespace {

using nlohmann::json;

Error err(const std::string& what) { return Error{"dvl: " + what}; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n' || s.back() == ' ')) s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\r' || s.front() == '\n')) s.remove_prefix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  size_t a = 0;
  for (;;) {
    const size_t b = s.find(sep, a);
    out.push_back(s.substr(a, b == std::string_view::npos ? std::string_view::npos : b - a));
    if (b == std::string_view::npos) break;
    a = b + 1;
  }
  return out;
}

std::optional<int64_t> to_int(std::string_view f) {
  int64_t v = 0;
  if (f.empty()) return std::nullopt;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec != std::errc() || r.ptr != f.data() + f.size()) return std::nullopt;
  return v;
}

std::optional<double> to_double(std::string_view f) {
  double v = 0;
  if (f.empty()) return std::nullopt;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string with_checksum(const std::string& body) {
  char cs[8];
  std::snprintf(cs, sizeof cs, "*%02X", nmea_checksum(body));
  return "$" + body + cs + "\r\n";
}

std::string num(double v) {  // lossless
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string g9(double v) {  // for people
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string boolean(bool b) { return b ? "true" : "false"; }

std::string quoted(const std::string& s) { return json(s).dump(); }

// ---- A50 -------------------------------------------------------------------------------------

// Reads typed keys of one JSON object; the first problem becomes `error`, naming the key.
class Keys {
 public:
  // `what` names the report in messages; `prefix` qualifies key names ("transducers[2].").
  Keys(const json& j, std::string what, std::string prefix = "")
      : j_(j), what_(std::move(what)), prefix_(std::move(prefix)) {}
  const json* find(const char* key, bool required) {
    const auto it = j_.find(key);
    if (it != j_.end()) return &*it;
    if (required) fail(name(key) + " is missing");
    return nullptr;
  }
  std::optional<double> number(const char* key, bool required) {
    const json* v = find(key, required);
    if (!v) return std::nullopt;
    if (!v->is_number()) return wrong(key, "a number", *v);
    const double d = v->get<double>();
    if (!std::isfinite(d)) return wrong(key, "a finite number", *v);
    return d;
  }
  std::optional<int64_t> integer(const char* key, bool required) {
    const json* v = find(key, required);
    if (!v) return std::nullopt;
    if (!v->is_number_integer()) return wrong(key, "an integer", *v);
    if (v->is_number_unsigned() && v->get<uint64_t>() > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()))
      return wrong(key, "an integer within 64 bits", *v);
    return v->get<int64_t>();
  }
  std::optional<bool> flag(const char* key, bool required) {
    const json* v = find(key, required);
    if (!v) return std::nullopt;
    if (!v->is_boolean()) return wrong(key, "a boolean", *v);
    return v->get<bool>();
  }
  std::optional<std::string> string(const char* key, bool required) {
    const json* v = find(key, required);
    if (!v) return std::nullopt;
    if (!v->is_string()) return wrong(key, "a string", *v);
    return v->get<std::string>();
  }
  void fail(const std::string& what) {
    if (!error) error = err(what_ + ": " + what);
  }
  std::string name(const char* key) const { return "\"" + prefix_ + key + "\""; }
  const std::string& what() const { return what_; }
  std::optional<Error> error;

 private:
  std::nullopt_t wrong(const char* key, const char* want, const json& got) {
    fail(name(key) + " must be " + want + ", not " + got.type_name());
    return std::nullopt;
  }
  const json& j_;
  std::string what_, prefix_;
};

// "json_v<major>[.<minor>]" with a supported major.
Result<int> format_major(const std::string& f) {
  constexpr std::string_view prefix = "json_v";
  if (f.rfind(prefix, 0) != 0) return err("A50 \"format\" \"" + f + "\" is not json_v<N>");
  const std::string_view rest = std::string_view(f).substr(prefix.size());
  const std::string_view major = rest.substr(0, rest.find('.'));
  const auto m = to_int(major);
  if (!m || (major.size() < rest.size() && !to_int(rest.substr(major.size() + 1))))
    return err("A50 \"format\" \"" + f + "\" is not json_v<major>[.<minor>]");
  if (*m < 1 || *m > 3) return err("A50 \"format\" \"" + f + "\" is not supported (json_v1 to json_v3.x)");
  return static_cast<int>(*m);
}

// The report's "format" (optional) into `format` and `major`; `major` keeps its default
// when the key is absent.
Status read_format(const json& j, const std::string& what, std::string& format, int& major, bool& present) {
  Keys k(j, what);
  const auto f = k.string("format", false);
  if (k.error) return *k.error;
  present = f.has_value();
  if (!f) return Status::Ok();
  auto m = format_major(*f);
  if (!m) return m.error();
  format = *f;
  major = *m;
  return Status::Ok();
}

// Transducers and covariance: present means well formed.
void read_transducers(Keys& k, std::vector<A50Transducer>& out) {
  const json* t = k.find("transducers", false);
  if (!t) return;
  if (!t->is_array()) return k.fail(std::string("\"transducers\" must be an array, not ") + t->type_name());
  for (size_t i = 0; i < t->size(); ++i) {
    const json& e = (*t)[i];
    const std::string prefix = "transducers[" + std::to_string(i) + "].";
    if (!e.is_object()) {
      return k.fail("\"transducers[" + std::to_string(i) + "]\" must be an object, not " + e.type_name());
    }
    Keys b(e, k.what(), prefix);
    A50Transducer x;
    x.id = b.integer("id", true).value_or(0);
    x.velocity_mps = b.number("velocity", true).value_or(0);
    x.distance_m = b.number("distance", true).value_or(0);
    x.rssi_dbm = b.number("rssi", true).value_or(0);
    x.nsd_dbm = b.number("nsd", true).value_or(0);
    x.beam_valid = b.flag("beam_valid", true).value_or(false);
    if (b.error) {
      if (!k.error) k.error = b.error;
      return;
    }
    out.push_back(x);
  }
}

std::optional<Eigen::Matrix3d> read_covariance(Keys& k) {
  const json* c = k.find("covariance", false);
  if (!c) return std::nullopt;
  Eigen::Matrix3d m;
  bool ok = c->is_array() && c->size() == 3;
  for (size_t r = 0; ok && r < 3; ++r) {
    const json& row = (*c)[r];
    ok = row.is_array() && row.size() == 3;
    for (size_t col = 0; ok && col < 3; ++col) {
      ok = row[col].is_number() && std::isfinite(row[col].get<double>());
      if (ok) m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(col)) = row[col].get<double>();
    }
  }
  if (!ok) {
    k.fail("\"covariance\" must be a 3x3 array of numbers");
    return std::nullopt;
  }
  return m;
}

Result<A50Decoded> decode_velocity(const json& j, std::optional<std::string> type) {
  A50Velocity r;
  bool has_format = false;
  if (Status st = read_format(j, "A50 velocity report", r.format, r.format_major, has_format); !st) return st.error();
  if (!has_format) r.format_major = j.contains("time_of_validity") ? 3 : 1;
  Keys v(j, "A50 " + (has_format ? r.format : "json_v" + std::to_string(r.format_major)) + " velocity report");
  if (!type && r.format_major > 1) v.fail("\"type\" is missing");
  r.type = type.value_or("");
  r.velocity.velocity_D_mps.x() = v.number("vx", true).value_or(0);
  r.velocity.velocity_D_mps.y() = v.number("vy", true).value_or(0);
  r.velocity.velocity_D_mps.z() = v.number("vz", true).value_or(0);
  r.velocity.valid = v.flag("velocity_valid", true).value_or(false);
  r.velocity.altitude_m = v.number("altitude", false).value_or(-1.0);
  r.time_ms = v.number("time", false);
  r.fom_mps = v.number("fom", false);
  r.status = v.integer("status", false);
  r.covariance_m2ps2 = read_covariance(v);
  r.time_of_validity_us = v.integer("time_of_validity", r.format_major >= 3);
  r.time_of_transmission_us = v.integer("time_of_transmission", false);
  r.tracking_mode = v.string("tracking_mode", false);
  read_transducers(v, r.transducers);
  if (v.error) return *v.error;
  return A50Decoded{std::move(r)};
}

Result<A50Decoded> decode_dead_reckoning(const json& j) {
  A50DeadReckoning r;
  bool has_format = false;
  if (Status st = read_format(j, "A50 dead-reckoning report", r.format, r.format_major, has_format); !st)
    return st.error();
  Keys d(j, "A50 " + (has_format ? r.format : std::string("json_v2")) + " dead-reckoning report");
  r.ts = d.number("ts", true).value_or(0);
  r.position_m.x() = d.number("x", true).value_or(0);
  r.position_m.y() = d.number("y", true).value_or(0);
  r.position_m.z() = d.number("z", true).value_or(0);
  // json_v2 documentation spells the figure of merit "pos_std" and, in its example, yaw "jaw".
  r.std_m = d.number(j.contains("std") || !j.contains("pos_std") ? "std" : "pos_std", true).value_or(0);
  r.roll_deg = d.number("roll", true).value_or(0);
  r.pitch_deg = d.number("pitch", true).value_or(0);
  r.yaw_deg = d.number(j.contains("yaw") || !j.contains("jaw") ? "yaw" : "jaw", true).value_or(0);
  r.status = d.integer("status", true).value_or(0);
  if (d.error) return *d.error;
  return A50Decoded{r};
}

std::string json_row(const Eigen::Matrix3d& m, Eigen::Index r, std::string (*fmt)(double)) {
  return "[" + fmt(m(r, 0)) + ", " + fmt(m(r, 1)) + ", " + fmt(m(r, 2)) + "]";
}

std::string covariance_text(const Eigen::Matrix3d& m, std::string (*fmt)(double)) {
  return "[" + json_row(m, 0, fmt) + ", " + json_row(m, 1, fmt) + ", " + json_row(m, 2, fmt) + "]";
}

// ---- PRTI ------------------------------------------------------------------------------------

const char* prti_field_name(size_t i) {
  static const char* names[] = {"sentence id", "start time", "sample number", "temperature",
                                "bottom-track velocity 1", "bottom-track velocity 2", "bottom-track velocity 3",
                                "bottom-track depth", "water-mass velocity 1", "water-mass velocity 2",
                                "water-mass velocity 3", "water-mass depth", "status", "subsystem", "CEPO index"};
  return i < std::size(names) ? names[i] : "field";
}

}  // namespace

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

// ---- A50 -------------------------------------------------------------------------------------

Result<A50Decoded> decode_a50(std::string_view line) {
  const json j = json::parse(trim(line), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return err("A50 line is not a JSON object");
  Keys k(j, "A50 report");
  const auto type = k.string("type", false);
  if (k.error) return *k.error;
  if (!type) {
    // json_v1 velocity reports may come without "type"; anything else must say what it is.
    if (!j.contains("vx")) return err("A50 report: \"type\" is missing");
    return decode_velocity(j, std::nullopt);
  }
  if (*type == "velocity" || *type == "velocity_water") return decode_velocity(j, type);
  if (*type == "position_local") return decode_dead_reckoning(j);
  return A50Decoded{A50Other{*type}};
}

Result<std::optional<A50Report>> A50Parser::parse(std::string_view line) {
  auto d = decode_a50(line);
  if (!d) {
    ++counters_.malformed;
    return d.error();
  }
  if (const auto* v = std::get_if<A50Velocity>(&*d)) {
    std::string key = v->time_of_validity_us ? "tov:" + std::to_string(*v->time_of_validity_us)
                                             : "line:" + std::string(trim(line));
    if (key == last_velocity_key_) {
      ++counters_.duplicates;
      return std::optional<A50Report>{};
    }
    last_velocity_key_ = std::move(key);
    ++counters_.velocity;
    return std::optional<A50Report>{A50Report{std::move(std::get<A50Velocity>(*d))}};
  }
  if (const auto* p = std::get_if<A50DeadReckoning>(&*d)) {
    if (last_dead_reckoning_ts_ == p->ts) {
      ++counters_.duplicates;
      return std::optional<A50Report>{};
    }
    last_dead_reckoning_ts_ = p->ts;
    ++counters_.dead_reckoning;
    return std::optional<A50Report>{A50Report{*p}};
  }
  ++counters_.other;
  return std::optional<A50Report>{};
}

Result<std::optional<DvlVelocity>> parse_a50_line(std::string_view line) {
  auto d = decode_a50(line);
  if (!d) return d.error();
  const auto* v = std::get_if<A50Velocity>(&*d);
  if (!v || !v->bottom_tracked()) return std::optional<DvlVelocity>{};
  return std::optional<DvlVelocity>{v->velocity};
}

std::string encode_a50(const A50Velocity& r) {
  // Key order as in the Water Linked documentation's examples.
  std::string s = "{";
  auto key = [&](const char* k, const std::string& value) {
    if (s.size() > 1) s += ", ";
    s += std::string("\"") + k + "\": " + value;
  };
  if (r.time_ms) key("time", num(*r.time_ms));
  key("vx", num(r.velocity.velocity_D_mps.x()));
  key("vy", num(r.velocity.velocity_D_mps.y()));
  key("vz", num(r.velocity.velocity_D_mps.z()));
  if (r.fom_mps) key("fom", num(*r.fom_mps));
  if (r.covariance_m2ps2) key("covariance", covariance_text(*r.covariance_m2ps2, num));
  key("altitude", num(r.velocity.altitude_m));
  if (!r.transducers.empty()) {
    std::string t = "[";
    for (const A50Transducer& x : r.transducers) {
      if (t.size() > 1) t += ", ";
      t += "{\"id\": " + std::to_string(x.id) + ", \"velocity\": " + num(x.velocity_mps) + ", \"distance\": " +
           num(x.distance_m) + ", \"rssi\": " + num(x.rssi_dbm) + ", \"nsd\": " + num(x.nsd_dbm) +
           ", \"beam_valid\": " + boolean(x.beam_valid) + "}";
    }
    key("transducers", t + "]");
  }
  key("velocity_valid", boolean(r.velocity.valid));
  if (r.status) key("status", std::to_string(*r.status));
  if (r.tracking_mode) key("tracking_mode", quoted(*r.tracking_mode));
  if (!r.format.empty()) key("format", quoted(r.format));
  if (!r.type.empty()) key("type", quoted(r.type));
  if (r.time_of_validity_us) key("time_of_validity", std::to_string(*r.time_of_validity_us));
  if (r.time_of_transmission_us) key("time_of_transmission", std::to_string(*r.time_of_transmission_us));
  return s + "}\n";
}

std::string encode_a50(const A50DeadReckoning& r) {
  std::string s = "{\"ts\": " + num(r.ts) + ", \"x\": " + num(r.position_m.x()) + ", \"y\": " +
                  num(r.position_m.y()) + ", \"z\": " + num(r.position_m.z()) + ", \"std\": " + num(r.std_m) +
                  ", \"roll\": " + num(r.roll_deg) + ", \"pitch\": " + num(r.pitch_deg) + ", \"yaw\": " +
                  num(r.yaw_deg) + ", \"type\": \"position_local\", \"status\": " + std::to_string(r.status);
  if (!r.format.empty()) s += ", \"format\": " + quoted(r.format);
  return s + "}\n";
}

std::string encode_a50_velocity(const DvlVelocity& v, double time_ms, std::optional<int64_t> time_of_validity_us) {
  assert(v.frame == DvlFrame::kInstrument);
  A50Velocity r;
  r.format = time_of_validity_us ? "json_v3.1" : "json_v2";
  r.format_major = time_of_validity_us ? 3 : 2;
  r.type = "velocity";
  r.velocity = v;
  r.time_ms = time_ms;
  r.status = 0;
  r.time_of_validity_us = time_of_validity_us;
  r.time_of_transmission_us = time_of_validity_us;
  return encode_a50(r);
}

// ---- PRTI ------------------------------------------------------------------------------------

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

// ---- Depth -----------------------------------------------------------------------------------

Result<DepthLine> parse_depth(std::string_view line) {
  line = trim(line);
  if (!line.empty() && line.front() == '{') {
    const json j = json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return err("depth line is not a JSON object");
    Keys k(j, "depth JSON");
    const auto d = k.number("depth", true);
    if (k.error) return *k.error;
    return DepthLine{*d, true};
  }
  auto body = nmea_body(line);
  if (!body) return body.error();
  const auto f = split(*body, ',');
  if (f.size() != 2 || f[0] != "DEPTH") return err("expected $DEPTH,<metres>");
  const auto d = to_double(f[1]);
  if (!d || *d < -100.0 || *d > 12000.0) return err("$DEPTH value is not a plausible number");
  return DepthLine{*d, false};
}

Result<double> parse_depth_line(std::string_view line) {
  auto d = parse_depth(line);
  if (!d) return d.error();
  return d->depth_m;
}

std::string encode_depth_line(double depth_m) { return with_checksum("DEPTH," + num(depth_m)); }

// ---- Inspection ------------------------------------------------------------------------------

FieldList describe(const A50Velocity& r) {
  FieldList out;
  if (!r.format.empty()) out.emplace_back("format", r.format);
  if (!r.type.empty()) out.emplace_back("type", r.type);
  if (r.time_ms) out.emplace_back("time", g9(*r.time_ms));
  out.emplace_back("vx", g9(r.velocity.velocity_D_mps.x()));
  out.emplace_back("vy", g9(r.velocity.velocity_D_mps.y()));
  out.emplace_back("vz", g9(r.velocity.velocity_D_mps.z()));
  if (r.fom_mps) out.emplace_back("fom", g9(*r.fom_mps));
  if (r.covariance_m2ps2) out.emplace_back("covariance", covariance_text(*r.covariance_m2ps2, g9));
  out.emplace_back("altitude", g9(r.velocity.altitude_m));
  for (size_t i = 0; i < r.transducers.size(); ++i) {
    const A50Transducer& t = r.transducers[i];
    out.emplace_back("transducers[" + std::to_string(i) + "]",
                     "id=" + std::to_string(t.id) + " velocity=" + g9(t.velocity_mps) + " distance=" +
                         g9(t.distance_m) + " rssi=" + g9(t.rssi_dbm) + " nsd=" + g9(t.nsd_dbm) +
                         " beam_valid=" + boolean(t.beam_valid));
  }
  out.emplace_back("velocity_valid", boolean(r.velocity.valid));
  if (r.status) out.emplace_back("status", std::to_string(*r.status));
  if (r.tracking_mode) out.emplace_back("tracking_mode", *r.tracking_mode);
  if (r.time_of_validity_us) out.emplace_back("time_of_validity", std::to_string(*r.time_of_validity_us));
  if (r.time_of_transmission_us) out.emplace_back("time_of_transmission", std::to_string(*r.time_of_transmission_us));
  return out;
}

FieldList describe(const A50DeadReckoning& r) {
  FieldList out;
  if (!r.format.empty()) out.emplace_back("format", r.format);
  out.emplace_back("type", "position_local");
  out.emplace_back("ts", g9(r.ts));
  out.emplace_back("x", g9(r.position_m.x()));
  out.emplace_back("y", g9(r.position_m.y()));
  out.emplace_back("z", g9(r.position_m.z()));
  out.emplace_back("std", g9(r.std_m));
  out.emplace_back("roll", g9(r.roll_deg));
  out.emplace_back("pitch", g9(r.pitch_deg));
  out.emplace_back("yaw", g9(r.yaw_deg));
  out.emplace_back("status", std::to_string(r.status));
  return out;
}

FieldList describe(const A50Other& r) { return {{"type", r.type}}; }
FieldList describe(const A50Decoded& r) {
  return std::visit([](const auto& x) { return describe(x); }, r);
}
FieldList describe(const A50Report& r) {
  return std::visit([](const auto& x) { return describe(x); }, r);
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

FieldList describe(const DepthLine& r) {
  return {{"form", r.json ? "json" : "$DEPTH"}, {"depth_m", g9(r.depth_m)}};
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
