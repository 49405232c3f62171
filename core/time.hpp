#pragma once
// Time as an integer count of nanoseconds (SPEC §1). A strong type: no implicit
// conversion to or from floating-point seconds, so interfaces never carry drifting
// doubles. Durations and instants share the type; the arithmetic below is what is
// meaningful for both.
#include <compare>
#include <cstdint>
#include <limits>

namespace orthosonar {

class Time {
 public:
  constexpr Time() = default;
  static constexpr Time from_ns(int64_t ns) { return Time(ns); }
  static constexpr Time from_us(int64_t us) { return Time(us * 1000); }
  static constexpr Time from_ms(int64_t ms) { return Time(ms * 1000000); }
  static constexpr Time from_s(int64_t s) { return Time(s * 1000000000); }
  // Rounds to the nearest nanosecond. For configuration values only (e.g. "0.1 s").
  static constexpr Time from_seconds(double s) {
    const double ns = s * 1e9;
    return Time(static_cast<int64_t>(ns < 0 ? ns - 0.5 : ns + 0.5));
  }
  static constexpr Time max() { return Time(std::numeric_limits<int64_t>::max()); }
  static constexpr Time min() { return Time(std::numeric_limits<int64_t>::min()); }

  constexpr int64_t ns() const { return ns_; }
  // Seconds as a double, for arithmetic inside an algorithm (never stored in an interface).
  constexpr double seconds() const { return static_cast<double>(ns_) * 1e-9; }

  constexpr Time operator+(Time o) const { return Time(ns_ + o.ns_); }
  constexpr Time operator-(Time o) const { return Time(ns_ - o.ns_); }
  constexpr Time operator-() const { return Time(-ns_); }
  constexpr Time& operator+=(Time o) { ns_ += o.ns_; return *this; }
  constexpr Time& operator-=(Time o) { ns_ -= o.ns_; return *this; }
  constexpr Time operator*(int64_t k) const { return Time(ns_ * k); }
  constexpr Time operator/(int64_t k) const { return Time(ns_ / k); }
  constexpr int64_t operator/(Time o) const { return ns_ / o.ns_; }
  constexpr Time operator%(Time o) const { return Time(ns_ % o.ns_); }
  constexpr auto operator<=>(const Time&) const = default;

 private:
  constexpr explicit Time(int64_t ns) : ns_(ns) {}
  int64_t ns_ = 0;
};

constexpr Time abs(Time t) { return t.ns() < 0 ? -t : t; }

}  // namespace orthosonar
