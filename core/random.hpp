#pragma once
// Deterministic random numbers (SPEC §9): a seeded engine with our own distribution code,
// because std:: distributions differ between standard libraries. Streams are derived
// from (seed, stream, index) so any single frame can be regenerated alone.
#include <cmath>
#include <cstdint>

namespace orthosonar {

// SplitMix64 finaliser: a bijective 64-bit mix, used to derive seeds.
constexpr uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// A seed for one independent stream, e.g. derive_seed(mission_seed, kSpeckleStream, ping_id).
constexpr uint64_t derive_seed(uint64_t seed, uint64_t stream, uint64_t index = 0) {
  return mix64(mix64(mix64(seed) ^ stream) ^ index);
}

// xoshiro256** engine. Same sequence on every platform and standard library.
class Rng {
 public:
  explicit Rng(uint64_t seed) {
    uint64_t z = seed;
    for (auto& s : s_) {
      z = mix64(z);
      s = z;
    }
  }
  uint64_t next_u64() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; the tiny bias is irrelevant here).
  uint64_t below(uint64_t n) {
    return static_cast<uint64_t>((static_cast<unsigned __int128>(next_u64()) * n) >> 64);
  }
  // Standard normal by Box-Muller (both values used, cached).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    // 2π as std::numbers::pi would give it (the same double), spelt out so that this header
    // also compiles as C++17 (the libtorch module under clang, core/inference/CMakeLists.txt).
    constexpr double kTwoPi = 2.0 * 3.141592653589793238462643383279502884;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(kTwoPi * u2);
    has_spare_ = true;
    return r * std::cos(kTwoPi * u2);
  }
  double normal(double mean, double sigma) { return mean + sigma * normal(); }
  // Exponential with the given mean.
  double exponential(double mean) {
    double u = uniform();
    while (u <= 0.0) u = uniform();
    return -mean * std::log(u);
  }

 private:
  static constexpr uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace orthosonar
