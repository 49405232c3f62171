#pragma once
// Test constructions for perception (header-only; used by fusion_test, fusion_slope_test and
// the fusion round-trip property): speckled pings with an Oculus-like non-uniform bearing table and
// point targets drawn at a known (range, angle).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "core/events.hpp"
#include "core/random.hpp"

namespace orthosonar::perception::testing {

// rows x cols over a 130° swath, denser at the centre like the Oculus tables, 0.05 m bins;
// exponential speckle of `mean`, clipped at `max_intensity`.
inline SonarPing speckle_ping(SonarMount mount, int rows, int cols, uint64_t seed, double mean,
                              double max_intensity = 255.0) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  SonarPing p;
  p.mount = mount;
  p.rows = static_cast<uint16_t>(rows);
  p.cols = static_cast<uint16_t>(cols);
  p.range_resolution_m = 0.05;
  for (int c = 0; c < cols; ++c) {
    const double u = -1.0 + 2.0 * (c + 0.5) / cols;
    p.bearings_rad.push_back(65.0 * kDeg * (u + 0.3 * u * u * u) / 1.3);
  }
  Rng rng(seed);
  p.image.resize(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  for (auto& x : p.image) x = static_cast<uint8_t>(std::min(max_intensity, rng.exponential(mean)));
  return p;
}

// The beam whose bearing is nearest `angle`.
inline int nearest_col(const SonarPing& p, double angle) {
  int best = 0;
  for (int c = 1; c < p.cols; ++c)
    if (std::abs(p.bearings_rad[static_cast<size_t>(c)] - angle) <
        std::abs(p.bearings_rad[static_cast<size_t>(best)] - angle))
      best = c;
  return best;
}

// Angular width of a beam (spacing to its neighbour).
inline double beam_width(const SonarPing& p, int col) {
  const int c = std::clamp(col, 1, p.cols - 1);
  return std::abs(p.bearings_rad[static_cast<size_t>(c)] - p.bearings_rad[static_cast<size_t>(c - 1)]);
}

// A 3x3 blob at the pixel nearest (range, angle): centre `peak`, the 8 neighbours `ring`
// (symmetric under a 90° rotation, so patch costs do not depend on the rotation's sense).
inline void draw_blob(SonarPing& p, double range_m, double angle_rad, uint8_t peak, uint8_t ring) {
  const int row = static_cast<int>(std::lround(range_m / p.range_resolution_m)) - 1;
  const int col = nearest_col(p, angle_rad);
  for (int dr = -1; dr <= 1; ++dr)
    for (int dc = -1; dc <= 1; ++dc)
      p.image[static_cast<size_t>((row + dr) * p.cols + col + dc)] = (dr == 0 && dc == 0) ? peak : ring;
}

// An h/v pair of 200 bins x 256 beams (±32°, uniform) on a flat background of 5.
inline std::pair<SonarPing, SonarPing> flat_pair() {
  SonarPing h, v;
  for (SonarPing* p : {&h, &v}) {
    p->rows = 200;
    p->cols = 256;
    p->range_resolution_m = 0.05;
    for (int c = 0; c < p->cols; ++c) p->bearings_rad.push_back((-32.0 + 64.0 * c / 255.0) * std::numbers::pi / 180.0);
    p->image.assign(static_cast<size_t>(p->rows) * p->cols, 5);
  }
  h.mount = SonarMount::kHorizontal;
  v.mount = SonarMount::kVertical;
  return {std::move(h), std::move(v)};
}

// Sets one 8-bit pixel.
inline void set_pixel(SonarPing& p, int row, int col, uint8_t x) {
  p.image[static_cast<size_t>(row) * p.cols + static_cast<size_t>(col)] = x;
}

}  // namespace orthosonar::perception::testing
