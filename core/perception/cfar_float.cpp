// The float CFAR path: per-cell prefix sums in double, O(1) per cell.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception::detail {

// Float images: prefix sums in double, in this exact order (the sums, hence the decisions,
// depend on the summation order). O(1) per cell.
std::vector<Detection> detect_float(const float* img, int rows, int cols, const CfarConfig& cfg) {
  using Acc = double;
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
  const double gate_d = cfg.gate;
  const int t = cfg.train_cells, g = cfg.guard_cells;
  const int max_n = cross ? 4 * t : 2 * t;
  const std::vector<double> alpha = alpha_table(max_n, cfg.pfa);

  double sums[4];
  int counts[4];
  for (int r = 0; r < rows; ++r) {
    // Range extents do not depend on the column.
    const int lead_lo = std::max(0, r - g - t), lead_hi = r - g;  // rows [lo, hi)
    const int lag_lo = r + g + 1, lag_hi = std::min(rows, r + g + 1 + t);
    const int n_lead = std::max(0, lead_hi - lead_lo), n_lag = std::max(0, lag_hi - lag_lo);
    while (computed < lag_hi) {  // P_{i+1} = P_i + row i
      const Acc* prev = prefix_row(computed);
      Acc* next = prefix_row(computed + 1);
      const float* src = img + static_cast<size_t>(computed) * C;
      for (size_t c = 0; c < C; ++c) next[c] = prev[c] + static_cast<Acc>(src[c]);
      ++computed;
    }
    const float* line = img + static_cast<size_t>(r) * C;
    size_t n_cand = 0;
    for (size_t c = 0; c < C; ++c) {
      cand[n_cand] = static_cast<int>(c);
      n_cand += static_cast<double>(line[c]) > gate_d ? 1u : 0u;
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
      const float x = line[c];
      int k = 0;
      if (n_lead > 0) {
        sums[k] = lead_b[c] - lead_a[c];
        counts[k++] = n_lead;
      }
      if (n_lag > 0) {
        sums[k] = lag_b[c] - lag_a[c];
        counts[k++] = n_lag;
      }
      if (cross) {
        const int left_lo = std::max(0, c - g - t), left_hi = c - g;
        const int right_lo = c + g + 1, right_hi = std::min(cols, c + g + 1 + t);
        if (left_hi > left_lo) {
          sums[k] = q[static_cast<size_t>(left_hi)] - q[static_cast<size_t>(left_lo)];
          counts[k++] = left_hi - left_lo;
        }
        if (right_hi > right_lo) {
          sums[k] = q[static_cast<size_t>(right_hi)] - q[static_cast<size_t>(right_lo)];
          counts[k++] = right_hi - right_lo;
        }
      }
      if (k == 0) continue;
      double s;
      int n;
      choose(cfg.method, sums, counts, k, s, n);
      const double xn = static_cast<double>(x) * static_cast<double>(n);
      const bool hit = !(s > 0.0) ? static_cast<double>(x) > 0.0  // β = 0
                                  : ratio_test(xn, alpha[static_cast<size_t>(n)], s);
      if (hit) out.push_back({r, c, static_cast<float>(x)});
    }
  }
  return filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

}  // namespace orthosonar::perception::detail
