#pragma once
// Per-cell CFAR references for tests and benchmarks, not used by the pipeline.
//
// Two references of the rule cfar.hpp states, both per cell and written for clarity:
//  - detect / cfar: the implementation before the row-wise fast path (prefix sums, O(1)
//    per cell, every cell above the gate tested on its own), kept (but for the rule
//    pieces below) as the reference the fast path must match bit for bit, always;
//  - naive_detect / naive_cfar: direct summation over the training cells, O(train cells)
//    per cell, the way the method is usually written (sonar-SLAM's `soca` loop): the
//    baseline of the side-by-side benchmark (cfar_bench.cpp).
// For integer images both give exactly the fast path's output (sums are exact integers,
// and the decision is fl(x N / S) > α in every implementation); for float images naive
// sums in its own order, so it agrees only where the sums are exact (integer values).
// The rule's scalar pieces (α, gate, choice of side, decision, speckle filter) are
// cfar_rule.hpp's, shared with the fast paths: what the reference checks is how the fast
// paths form the sums and apply the rule to every cell, and naive_detect keeps its own
// choice of side and decision as an independent check of those.
// Plus the image of the side-by-side benchmark (issue 37), shared with its unit test.
// Header-only, for test and benchmark programs.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "core/events.hpp"
#include "core/perception/cfar.hpp"
#include "core/perception/cfar_rule.hpp"
#include "core/random.hpp"

namespace orthosonar::perception::reference {

// Prefix sums along range (per column) and along bearing (per row): O(1) per cell.
// Acc is exact (integer) for integer images, so the ratio test below is exactly
// scale-invariant: x N / S is a correctly rounded quotient of exactly scaled integers.
template <class Pixel, class Acc>
std::vector<Detection> detect(const Pixel* img, int rows, int cols, const CfarConfig& cfg) {
  std::vector<Detection> out;
  if (rows <= 0 || cols <= 0 || cfg.train_cells <= 0 || cfg.guard_cells < 0) return out;
  const size_t C = static_cast<size_t>(cols);
  const bool cross = cfg.window == CfarWindow::kCross;
  // Column prefix sums along range, P_i[c] = sum of rows [0, i) in column c, kept in a
  // ring of the K most recent rows: a cell only ever needs P between its leading and
  // lagging window ends, at most 2(g + t) + 1 rows apart. O(K cols) memory, cache-resident.
  const int K = 2 * (cfg.guard_cells + cfg.train_cells) + 2;
  std::vector<Acc> ring(static_cast<size_t>(K) * C, Acc{0});
  auto prefix_row = [&](int i) { return ring.data() + static_cast<size_t>(i % K) * C; };
  int computed = 0;  // P_0 .. P_computed are available (P_0 = 0 is the ring's zero row)
  // Row prefix sums along bearing for the current row: Q[c] = sum of cols [0, c).
  std::vector<Acc> q(C + 1, Acc{0});
  std::vector<int> cand(C);
  const int64_t gate_i = detail::integer_gate(cfg.gate);
  const double gate_d = cfg.gate;
  auto above_gate = [gate_i, gate_d](Pixel x) {
    if constexpr (std::is_integral_v<Pixel>) {
      return static_cast<int64_t>(x) > gate_i;
    } else {
      return static_cast<double>(x) > gate_d;
    }
  };
  const int t = cfg.train_cells, g = cfg.guard_cells;
  const int max_n = cross ? 4 * t : 2 * t;
  const std::vector<double> alpha = detail::alpha_table(max_n, cfg.pfa);

  using Wide = std::conditional_t<std::is_integral_v<Acc>, int64_t, double>;
  Wide sums[4];
  int counts[4];
  for (int r = 0; r < rows; ++r) {
    // Range extents do not depend on the column.
    const int lead_lo = std::max(0, r - g - t), lead_hi = r - g;  // rows [lo, hi)
    const int lag_lo = r + g + 1, lag_hi = std::min(rows, r + g + 1 + t);
    const int n_lead = std::max(0, lead_hi - lead_lo), n_lag = std::max(0, lag_hi - lag_lo);
    while (computed < lag_hi) {  // P_{i+1} = P_i + row i
      const Acc* prev = prefix_row(computed);
      Acc* next = prefix_row(computed + 1);
      const Pixel* src = img + static_cast<size_t>(computed) * C;
      for (size_t c = 0; c < C; ++c) next[c] = prev[c] + static_cast<Acc>(src[c]);
      ++computed;
    }
    const Pixel* line = img + static_cast<size_t>(r) * C;
    // Cells above the gate, branch-free (most of a sonar image is below it).
    size_t n_cand = 0;
    for (size_t c = 0; c < C; ++c) {
      cand[n_cand] = static_cast<int>(c);
      n_cand += above_gate(line[c]) ? 1u : 0u;
    }
    if (n_cand == 0) continue;
    if (cross) {
      Acc acc{0};
      for (size_t c = 0; c < C; ++c) {
        acc += static_cast<Acc>(line[c]);
        q[c + 1] = acc;
      }
    }
    const Acc* lead_a = prefix_row(std::max(lead_lo, 0));
    const Acc* lead_b = prefix_row(std::max(lead_hi, 0));
    const Acc* lag_a = prefix_row(std::min(lag_lo, rows));
    const Acc* lag_b = prefix_row(lag_hi);
    for (size_t ci = 0; ci < n_cand; ++ci) {
      const int c = cand[ci];
      const Pixel x = line[c];
      int k = 0;
      if (n_lead > 0) {
        sums[k] = static_cast<Wide>(lead_b[c] - lead_a[c]);
        counts[k++] = n_lead;
      }
      if (n_lag > 0) {
        sums[k] = static_cast<Wide>(lag_b[c] - lag_a[c]);
        counts[k++] = n_lag;
      }
      if (cross) {
        const int left_lo = std::max(0, c - g - t), left_hi = c - g;
        const int right_lo = c + g + 1, right_hi = std::min(cols, c + g + 1 + t);
        if (left_hi > left_lo) {
          sums[k] = static_cast<Wide>(q[static_cast<size_t>(left_hi)] - q[static_cast<size_t>(left_lo)]);
          counts[k++] = left_hi - left_lo;
        }
        if (right_hi > right_lo) {
          sums[k] = static_cast<Wide>(q[static_cast<size_t>(right_hi)] - q[static_cast<size_t>(right_lo)]);
          counts[k++] = right_hi - right_lo;
        }
      }
      if (k == 0) continue;
      Wide s;
      int n;
      detail::choose(cfg.method, sums, counts, k, s, n);  // the rule's choice of side (cfar_rule.hpp)
      const Wide xn = static_cast<Wide>(x) * static_cast<Wide>(n);
      const bool hit = !(s > Wide{0}) ? static_cast<double>(x) > 0.0  // β = 0
                                      : detail::ratio_test(static_cast<double>(xn), alpha[static_cast<size_t>(n)],
                                                           static_cast<double>(s));
      if (hit) out.push_back({r, c, static_cast<float>(x)});
    }
  }
  return detail::filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

// 16-bit little-endian ping pixels as values.
inline std::vector<uint16_t> widen(const SonarPing& ping) {
  const size_t n = static_cast<size_t>(ping.rows) * static_cast<size_t>(ping.cols);
  std::vector<uint16_t> wide(n);
  for (size_t i = 0; i < n; ++i)
    wide[i] = static_cast<uint16_t>(ping.image[2 * i] | (ping.image[2 * i + 1] << 8));
  return wide;
}

inline std::vector<Detection> cfar(const SonarPing& ping, const CfarConfig& config) {
  const int rows = ping.rows, cols = ping.cols;
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (ping.bytes_per_pixel == 1) {
    if (ping.image.size() < n) return {};
    return detect<uint8_t, int32_t>(ping.image.data(), rows, cols, config);
  }
  if (ping.image.size() < 2 * n) return {};
  const std::vector<uint16_t> wide = widen(ping);
  return detect<uint16_t, int64_t>(wide.data(), rows, cols, config);
}

inline std::vector<Detection> cfar(const float* image, int rows, int cols, const CfarConfig& config) {
  return detect<float, double>(image, rows, cols, config);
}

// ---------------------------------------------------------------------------------------
// Direct summation: for every cell above the gate, each training side summed cell by cell
// (k = g + 1 .. g + t from the cell, the cells inside the image), then the same choice of
// side and the same rule, fl(x N / S) > α (β = 0 when S = 0). Sums are exact integers for
// integer pixels (int64), doubles in that order for float pixels. O(t) per cell.
template <class Pixel>
std::vector<Detection> naive_detect(const Pixel* img, int rows, int cols, const CfarConfig& cfg) {
  std::vector<Detection> out;
  if (rows <= 0 || cols <= 0 || cfg.train_cells <= 0 || cfg.guard_cells < 0) return out;
  using Wide = std::conditional_t<std::is_integral_v<Pixel>, int64_t, double>;
  const int t = cfg.train_cells, g = cfg.guard_cells;
  const bool cross = cfg.window == CfarWindow::kCross;
  const int max_n = cross ? 4 * t : 2 * t;
  const std::vector<double> alpha = detail::alpha_table(max_n, cfg.pfa);
  const auto stride = static_cast<ptrdiff_t>(cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const Pixel* cut = img + static_cast<ptrdiff_t>(r) * stride + c;
      const Pixel x = *cut;
      if (!(static_cast<double>(x) > cfg.gate)) continue;
      Wide sums[4];
      int counts[4];
      int m = 0;
      // One side: `room` cells exist beyond the CUT in direction `step`.
      auto side = [&](int room, ptrdiff_t step) {
        const int last = std::min(g + t, room);
        if (last <= g) return;
        Wide s{0};
        for (int k = g + 1; k <= last; ++k) s += static_cast<Wide>(cut[k * step]);
        sums[m] = s;
        counts[m++] = last - g;
      };
      side(r, -stride);            // leading (towards row 0)
      side(rows - 1 - r, stride);  // lagging
      if (cross) {
        side(c, -1);             // left
        side(cols - 1 - c, 1);  // right
      }
      if (m == 0) continue;
      Wide s = sums[0];
      int n = counts[0];
      for (int i = 1; i < m; ++i) {
        if (cfg.method == CfarMethod::kCa) {
          s += sums[i];
          n += counts[i];
          continue;
        }
        const Wide a = sums[i] * static_cast<Wide>(n), b = s * static_cast<Wide>(counts[i]);
        if (cfg.method == CfarMethod::kSoca ? a < b : a > b) {  // ties keep the earlier side
          s = sums[i];
          n = counts[i];
        }
      }
      const double xd = static_cast<double>(x);
      const bool hit = s > Wide{0} ? xd * n / static_cast<double>(s) > alpha[static_cast<size_t>(n)] : xd > 0.0;
      if (hit) out.push_back({r, c, static_cast<float>(x)});
    }
  }
  return detail::filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

inline std::vector<Detection> naive_cfar(const SonarPing& ping, const CfarConfig& config) {
  const int rows = ping.rows, cols = ping.cols;
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (ping.bytes_per_pixel == 1) {
    if (ping.image.size() < n) return {};
    return naive_detect<uint8_t>(ping.image.data(), rows, cols, config);
  }
  if (ping.image.size() < 2 * n) return {};
  const std::vector<uint16_t> wide = widen(ping);
  return naive_detect<uint16_t>(wide.data(), rows, cols, config);
}

// ---------------------------------------------------------------------------------------
// The side-by-side benchmark's image (issue 37): rows x cols 8-bit, exponential speckle
// of the given mean (floored, capped at 255) and `targets` bright blobs (1-3 x 1-3 cells
// at 150-255, anywhere), all from `seed`. Full size: 600 x 512, mean 20, 300 targets.
inline SonarPing speckle_with_targets(int rows, int cols, double mean, int targets, uint64_t seed) {
  SonarPing p;
  p.rows = static_cast<uint16_t>(rows);
  p.cols = static_cast<uint16_t>(cols);
  p.bytes_per_pixel = 1;
  p.image.resize(static_cast<size_t>(rows) * static_cast<size_t>(cols));
  Rng rng(seed);
  for (uint8_t& x : p.image) x = static_cast<uint8_t>(std::min(255.0, std::floor(rng.exponential(mean))));
  for (int i = 0; i < targets; ++i) {
    const int r0 = static_cast<int>(rng.below(static_cast<uint64_t>(rows)));
    const int c0 = static_cast<int>(rng.below(static_cast<uint64_t>(cols)));
    const int h = 1 + static_cast<int>(rng.below(3)), w = 1 + static_cast<int>(rng.below(3));
    for (int r = r0; r < std::min(rows, r0 + h); ++r)
      for (int c = c0; c < std::min(cols, c0 + w); ++c)
        p.image[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)] =
            static_cast<uint8_t>(150 + rng.below(106));
  }
  return p;
}

// The benchmark's configuration on that image: SOCA, 20 training and 5 guard cells per
// side, Pfa 0.1, no speckle filter; `gate` -1 tests every cell.
inline CfarConfig speckle_with_targets_config(CfarWindow window, double gate) {
  CfarConfig cfg;
  cfg.method = CfarMethod::kSoca;
  cfg.window = window;
  cfg.train_cells = 20;
  cfg.guard_cells = 5;
  cfg.pfa = 0.1;
  cfg.gate = gate;
  cfg.min_neighbours = 0;
  return cfg;
}

// Bit-for-bit equality of two detection lists (intensities compared as bytes).
inline bool same_detections(const std::vector<Detection>& a, const std::vector<Detection>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].row != b[i].row || a[i].col != b[i].col) return false;
    if (std::memcmp(&a[i].intensity, &b[i].intensity, sizeof(float)) != 0) return false;
  }
  return true;
}

}  // namespace orthosonar::perception::reference
