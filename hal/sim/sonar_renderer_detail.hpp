#pragma once
// What the sonar renderer's stages share (internal): table sizes, the per-mount tables
// (sonar_head_tables.cpp), the renderer's state, the beam lookup and the per-thread
// scratch of the echo accumulation (sonar_echo.cpp) and the image assembly
// (sonar_renderer.cpp).
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/geometry.hpp"
#include "core/random.hpp"
#include "hal/sim/embree_device.hpp"
#include "hal/sim/sonar_renderer.hpp"

namespace orthosonar::sim {

namespace detail {

constexpr int kTable = 4096;     // speckle / noise inverse-CDF tables (12-bit index)
constexpr int kGammaLut = 16384;  // linear [0, 1] -> 8-bit
constexpr int kCosTable = 1024;
constexpr uint64_t kRayPatternStream = 0x52415950415454ull;  // fixed device ray pattern
constexpr int kApLut = 4096;
constexpr int kTexLut = 2048;

}  // namespace detail

// Per-mount tables: the device's bearing table, ray pattern and range-dependent gains.
struct HeadTables {
  SonarHead spec;
  SonarGeometry geo;
  std::vector<double> bearings;
  std::vector<float> tan_mid;           // tan of the midpoints between beams (beam lookup)
  float tan_lo = 0.0f, tan_hi = 0.0f;   // tan of the fan's outer edges
  int rays_per_beam = 0;
  // Ray pattern in the sonar frame, beam-major, and each ray's weight (aperture pattern,
  // normalised per beam) and its unnormalised aperture gain G(phi).
  std::vector<float> dx, dy, dz, weight, gain_ap;
  // Per ray: d(direction)/d(elevation) in the sonar frame (unit), and cos and sin of the
  // offsets from the ray's (jittered) elevation to its stratum's lower and upper bounds:
  // the direction at offset delta is cos(delta) d + sin(delta) e, so a hit's range
  // footprint on its plane follows exactly. Built only with sonar.range_footprint.
  std::vector<float> ex, ey, ez, lo_cos, lo_sin, hi_cos, hi_sin;
  std::vector<float> row_signal;        // spreading * absorption * TVG * bin-width normalisation
  std::vector<float> row_noise;         // TVG applied to the noise floor (1: range-independent)
  std::vector<float> side_min;          // per row: the weakest echo whose side lobes can show
  // Beam pattern as a scatter kernel: echo in beam j adds k_main[j][k] (k = -main_half..)
  // to beams j + k, and, when strong, k_side taps (offset, weight) further out.
  int main_half = 0;
  std::vector<float> k_main;            // beams x (2 main_half + 1)
  std::vector<std::vector<std::pair<int, float>>> k_side;
  float side_peak = 0.0f;               // the largest side-lobe tap (relative to the echo)
  int reach = 0;                        // the farthest tap from its source beam (main or side; 0 without a pattern)
  double absorption_db_per_m = 0.0;
  // Per ray: sqrt(max G / G(ray)), the largest factor a multipath ghost can get (early out).
  std::vector<float> ghost_bound;
  // With a range-independent noise gain: the byte of an empty pixel per noise-table index.
  std::vector<uint8_t> zero_lut;
};

struct SonarRenderer::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  SonarModelConfig cfg;
  uint64_t seed = 0;
  HeadTables heads[2];                        // indexed by SonarMount
  std::vector<Eigen::Vector3f> normal;  // unit normal per triangle
  std::vector<float> reflect;           // reflectivity per triangle
  std::vector<uint8_t> semantic;
  std::vector<uint32_t> object;
  std::vector<float> cos_pow;           // cos(incidence)^k on [0, 1]
  std::vector<float> gap_lut;           // aperture gain G(phi) against sin(phi) on [-1, 1]
  std::vector<float> texture_lut;       // exp(sigma t - sigma^2 / 2) for t on [-4, 4]
  std::vector<float> speckle, noise;
  std::vector<uint8_t> gamma_lut;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace detail {

// Inverse CDF of Gamma(L, 1/L) (mean 1) at the centres of kTable equal-probability cells.
std::vector<float> erlang_table(int looks);

// The per-mount tables of one head (bearings, ray pattern, gains, beam pattern kernel).
void build_head(HeadTables& h, const SonarHead& spec, const SonarModelConfig& cfg, Resolution resolution);

// The beam whose sector contains tan(bearing) = y / x, or -1 outside the fan.
inline int beam_of(const HeadTables& h, float y, float x) {
  if (!(x > 0.0f)) return -1;
  const float t = y / x;
  if (t < h.tan_lo || t > h.tan_hi) return -1;
  return static_cast<int>(std::upper_bound(h.tan_mid.begin(), h.tan_mid.end(), t) - h.tan_mid.begin());
}

// Per-thread, per-mount scratch of accumulate/render, reused from ping to ping (no
// allocation or page faults per ping once warm). render() is const and may run on several
// threads at once: each thread has its own.
//
// accum and spread are kept all zero between pings: a ping clears only the cells it may
// have written (per row, the columns [lo, hi] of deposits, widened by the beam pattern's
// reach), so the images are not zeroed whole twice per ping. A buffer that left the
// scratch (echo() hands it out) comes back empty and is zeroed whole.
struct Scratch {
  std::vector<float> accum, spread, best, best_spread;
  std::vector<uint8_t> sem;
  std::vector<uint32_t> obj;
  std::vector<int> col_lo, col_hi;  // per row: the columns anything was deposited in (lo > hi: none)
};
Scratch& scratch(SonarMount mount);

// An all-zero buffer of n floats: `v` as the scratch left it (all zero) when its size is n,
// else zeroed whole.
inline void take_zeroed(std::vector<float>& v, size_t n) {
  if (v.size() != n) v.assign(n, 0.0f);
}

// Zeroes, per row, the columns [lo[row] - widen, hi[row] + widen] within the image (none
// where lo > hi): what a ping wrote, widened by the beam pattern's reach where it spread.
inline void clear_rows(std::vector<float>& v, int cols, const std::vector<int>& lo, const std::vector<int>& hi, int widen) {
  for (size_t r = 0; r < lo.size(); ++r) {
    if (lo[r] > hi[r]) continue;
    float* row = v.data() + r * static_cast<size_t>(cols);
    std::fill(row + std::max(0, lo[r] - widen), row + std::min(cols - 1, hi[r] + widen) + 1, 0.0f);
  }
}

}  // namespace detail

}  // namespace orthosonar::sim
