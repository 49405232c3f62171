#include "hal/drivers/dvl_protocols.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

namespace orthosonar::hal::drivers::dvl {
namespace {

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

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
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

Result<std::optional<DvlVelocity>> parse_a50_line(std::string_view line) {
  const nlohmann::json j = nlohmann::json::parse(trim(line), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return err("A50 line is not a JSON object");
  const auto type = j.find("type");
  if (type == j.end() || !type->is_string()) return err("A50 report without a \"type\"");
  if (type->get<std::string>() != "velocity") return std::optional<DvlVelocity>{};
  DvlVelocity v;
  const char* keys[3] = {"vx", "vy", "vz"};
  for (int i = 0; i < 3; ++i) {
    const auto f = j.find(keys[i]);
    if (f == j.end() || !f->is_number()) return err(std::string("A50 velocity report without numeric \"") + keys[i] + "\"");
    v.velocity_D_mps[i] = f->get<double>();
  }
  const auto valid = j.find("velocity_valid");
  if (valid == j.end() || !valid->is_boolean()) return err("A50 velocity report without boolean \"velocity_valid\"");
  v.valid = valid->get<bool>();
  const auto alt = j.find("altitude");
  if (alt != j.end() && alt->is_number()) v.altitude_m = alt->get<double>();
  if (!v.velocity_D_mps.allFinite() || !std::isfinite(v.altitude_m)) return err("A50 values not finite");
  return std::optional<DvlVelocity>{v};
}

std::string encode_a50_velocity(const DvlVelocity& v, double time_ms) {
  // Key order as the device sends it (field order does not matter to parsers).
  return "{\"time\": " + num(time_ms) + ", \"vx\": " + num(v.velocity_D_mps.x()) + ", \"vy\": " +
         num(v.velocity_D_mps.y()) + ", \"vz\": " + num(v.velocity_D_mps.z()) + ", \"fom\": 0.002, \"altitude\": " +
         num(v.altitude_m) + ", \"velocity_valid\": " + (v.valid ? "true" : "false") +
         ", \"status\": 0, \"format\": \"json_v3.1\", \"type\": \"velocity\"}\n";
}

Result<DvlVelocity> parse_prti01(std::string_view line) {
  auto body = nmea_body(line);
  if (!body) return body.error();
  const auto f = split(*body, ',');
  if (f.size() != 13 || f[0] != "PRTI01") return err("$PRTI01 needs 12 fields after the talker");
  for (int i : {1, 2, 3}) if (!to_int(f[static_cast<size_t>(i)])) return err("$PRTI01 field " + std::to_string(i) + " is not an integer");
  DvlVelocity v;
  v.valid = true;
  for (int i = 0; i < 3; ++i) {
    const auto mm = to_int(f[static_cast<size_t>(4 + i)]);
    if (!mm) return err("$PRTI01 bottom-track velocity field " + std::to_string(4 + i) + " is not an integer");
    if (*mm == kRoweInvalid) {
      v.valid = false;
    } else {
      if (*mm < -100000 || *mm > 100000) return err("$PRTI01 velocity out of range");
      v.velocity_D_mps[i] = static_cast<double>(*mm) / 1000.0;
    }
  }
  if (!v.valid) v.velocity_D_mps.setZero();
  const auto depth = to_int(f[7]);
  if (!depth) return err("$PRTI01 bottom-track depth is not an integer");
  v.altitude_m = *depth > 0 ? static_cast<double>(*depth) / 1000.0 : -1.0;
  return v;
}

std::string encode_prti01(const DvlVelocity& v, uint32_t sample, uint32_t start_time_cs) {
  auto mm = [&](int i) -> std::string {
    if (!v.valid) return std::to_string(kRoweInvalid);
    return std::to_string(static_cast<int64_t>(std::llround(v.velocity_D_mps[i] * 1000.0)));
  };
  const int64_t depth_mm = v.altitude_m > 0 ? std::llround(v.altitude_m * 1000.0) : 0;
  const std::string body = "PRTI01," + std::to_string(start_time_cs) + "," + std::to_string(sample) + ",1464," + mm(0) +
                           "," + mm(1) + "," + mm(2) + "," + std::to_string(depth_mm) + ",,,,,0004";
  return with_checksum(body);
}

Result<double> parse_depth_line(std::string_view line) {
  line = trim(line);
  if (!line.empty() && line.front() == '{') {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return err("depth line is not a JSON object");
    const auto d = j.find("depth");
    if (d == j.end() || !d->is_number() || !std::isfinite(d->get<double>())) return err("depth JSON without numeric \"depth\"");
    return d->get<double>();
  }
  auto body = nmea_body(line);
  if (!body) return body.error();
  const auto f = split(*body, ',');
  if (f.size() != 2 || f[0] != "DEPTH") return err("expected $DEPTH,<metres>");
  const auto d = to_double(f[1]);
  if (!d || *d < -100.0 || *d > 12000.0) return err("$DEPTH value is not a plausible number");
  return *d;
}

std::string encode_depth_line(double depth_m) { return with_checksum("DEPTH," + num(depth_m)); }

Quat default_a50_mount() { return Quat(0.0, 1.0, 0.0, 0.0); }

DvlReading to_dvl_reading(const DvlVelocity& v, const Quat& q_V_D, Time stamp) {
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
