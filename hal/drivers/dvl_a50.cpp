// Water Linked DVL A50 JSON reports: decoding every firmware format, encoding, inspection.
#include "hal/drivers/dvl_protocols.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "hal/drivers/dvl_detail.hpp"

namespace orthosonar::hal::drivers::dvl {

using namespace detail;

namespace {

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

}  // namespace

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

}  // namespace orthosonar::hal::drivers::dvl
