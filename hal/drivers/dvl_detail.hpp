#pragma once
// What the DVL and depth line protocols share (internal): field splitting and number
// parsing, NMEA checksums on output, number formatting, and the typed JSON key reader.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "hal/drivers/dvl_protocols.hpp"

namespace orthosonar::hal::drivers::dvl::detail {

using nlohmann::json;

inline Error err(const std::string& what) { return Error{"dvl: " + what}; }

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == '\n' || s.back() == ' ')) s.remove_suffix(1);
  while (!s.empty() && (s.front() == ' ' || s.front() == '\r' || s.front() == '\n')) s.remove_prefix(1);
  return s;
}

inline std::vector<std::string_view> split(std::string_view s, char sep) {
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

inline std::optional<int64_t> to_int(std::string_view f) {
  int64_t v = 0;
  if (f.empty()) return std::nullopt;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec != std::errc() || r.ptr != f.data() + f.size()) return std::nullopt;
  return v;
}

inline std::optional<double> to_double(std::string_view f) {
  double v = 0;
  if (f.empty()) return std::nullopt;
  const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
  if (r.ec != std::errc() || r.ptr != f.data() + f.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

inline std::string with_checksum(const std::string& body) {
  char cs[8];
  std::snprintf(cs, sizeof cs, "*%02X", nmea_checksum(body));
  return "$" + body + cs + "\r\n";
}

inline std::string num(double v) {  // lossless
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

inline std::string g9(double v) {  // for people
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

inline std::string boolean(bool b) { return b ? "true" : "false"; }

inline std::string quoted(const std::string& s) { return json(s).dump(); }

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

}  // namespace orthosonar::hal::drivers::dvl::detail
