#pragma once
// The CFAR rule's scalar pieces (cfar.hpp): α per training-cell count, the integer gate,
// the SOCA / GOCA / CA choice of side, the decision fl(x N / S) > α and the isolated-
// speckle filter. Shared by the fast paths (cfar_*.cpp) and the per-cell reference
// (cfar_reference.hpp); the naive reference keeps its own choice and decision.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/perception/cfar.hpp"

namespace orthosonar::perception::detail {

// alpha[N] = cfar_alpha(N, pfa) for N in [1, max_n]; alpha[0] = 0 (never used).
inline std::vector<double> alpha_table(int max_n, double pfa) {
  std::vector<double> alpha(static_cast<size_t>(max_n) + 1, 0.0);
  for (int n = 1; n <= max_n; ++n) alpha[static_cast<size_t>(n)] = cfar_alpha(n, pfa);
  return alpha;
}

// x > gate, exactly, in the pixel's own type: for integers x > gate <=> x > floor(gate).
inline int64_t integer_gate(double gate) {
  return static_cast<int64_t>(std::floor(std::clamp(gate, -1.0, 1e6)));
}

// SOCA / GOCA over the k non-empty sides in the fixed order (lead, lag, left, right):
// means s_i / n_i compared exactly by cross-multiplication, ties keep the first side.
// CA: all training cells. k > 0. T is int64_t (exact integer sums) or double.
template <class T>
inline void choose(CfarMethod method, const T* sums, const int* counts, int k, T& s, int& n) {
  s = sums[0];
  n = counts[0];
  if (method == CfarMethod::kCa) {
    for (int i = 1; i < k; ++i) {
      s += sums[i];
      n += counts[i];
    }
  } else if (method == CfarMethod::kSoca) {
    for (int i = 1; i < k; ++i) {
      const bool take = sums[i] * static_cast<T>(n) < s * static_cast<T>(counts[i]);
      s = take ? sums[i] : s;
      n = take ? counts[i] : n;
    }
  } else {
    for (int i = 1; i < k; ++i) {
      const bool take = sums[i] * static_cast<T>(n) > s * static_cast<T>(counts[i]);
      s = take ? sums[i] : s;
      n = take ? counts[i] : n;
    }
  }
}

// The detection rule for a training sum S > 0 of N cells: fl(x N / S) > α, a correctly
// rounded quotient of exactly scaled sums, hence exactly scale-invariant for integer
// images. Products decide it unless x N is within a relative 1e-12 of α S, where the
// quotient itself is computed. lhs = x N, s = S, both exact.
inline bool ratio_test(double lhs, double a, double s) {
  const double rhs = a * s;
  if (lhs > rhs * (1.0 + 1e-12)) return true;
  if (lhs < rhs * (1.0 - 1e-12)) return false;
  return lhs / s > a;
}

// Keeps detections with at least `min_n` of their 8 neighbours detected (neighbours
// counted in the unfiltered set), using a rows x cols occupancy mask.
inline std::vector<Detection> filter_isolated(std::vector<Detection> dets, int min_n, int rows, int cols) {
  if (min_n <= 0 || dets.empty()) return dets;
  const size_t C = static_cast<size_t>(cols);
  std::vector<uint8_t> mask(static_cast<size_t>(rows) * C, 0);
  for (const Detection& d : dets) mask[static_cast<size_t>(d.row) * C + static_cast<size_t>(d.col)] = 1;
  std::vector<Detection> kept;
  kept.reserve(dets.size());
  for (const Detection& d : dets) {
    int n = 0;
    for (int r = std::max(0, d.row - 1); r <= std::min(rows - 1, d.row + 1); ++r)
      for (int c = std::max(0, d.col - 1); c <= std::min(cols - 1, d.col + 1); ++c)
        n += mask[static_cast<size_t>(r) * C + static_cast<size_t>(c)];
    if (n - 1 >= min_n) kept.push_back(d);  // minus the cell itself
  }
  return kept;
}

}  // namespace orthosonar::perception::detail
