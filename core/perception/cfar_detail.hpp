#pragma once
// What the CFAR implementation files share (internal): the training sides of a row, the
// row kernels (cfar_row_kernels.cpp), the 8-bit threshold table (cfar_threshold_table.cpp),
// the fused 8-bit SSE2 decision (cfar_uniform_hits.cpp) and the paths per pixel type
// (cfar_float.cpp, cfar_integer.cpp) that cfar.cpp dispatches to.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/perception/cfar.hpp"
#include "core/perception/cfar_rule.hpp"

namespace orthosonar::perception::detail {

// The paths per pixel type; each returns the filtered detections.
std::vector<Detection> detect_float(const float* img, int rows, int cols, const CfarConfig& cfg);
std::vector<Detection> detect_integer(const uint8_t* img, int rows, int cols, const CfarConfig& cfg);
std::vector<Detection> detect_integer(const uint16_t* img, int rows, int cols, const CfarConfig& cfg);

// ---------------------------------------------------------------------------------------
// Integer images (8 and 16 bit): cfar_integer.cpp. Sums are exact integers, so the order
// in which they are formed does not matter and a row can be processed as a whole:
//  - along range, a ring of column prefix sums (Acc, unsigned: differences are exact
//    modulo 2^bits and every window sum fits);
//  - along bearing, the row's prefix sums, or direct sums for a few cells;
//  - in a row's interior columns all four sides have full counts (the range counts only
//    depend on the row, the bearing counts only on the column), so SOCA is the minimum of
//    the sums, GOCA the maximum, CA the total: computed 4 columns at a time;
//  - 8-bit, sane α: the decision is an integer compare S <= smax[N][x], where smax[N][x]
//    is the largest sum of N cells for which x is a detection (-1: none, also at or below
//    the gate). The rule is monotone in S (below), so the table is derived from the exact
//    rule itself and the compare is the rule, bit for bit.
//  - rows with few cells above the gate only test those cells.

// One training side: its sum at column c is hi[c + off_hi] - lo[c + off_lo] (exact modulo
// 2^bits, and it fits), its count `counts[c]` when counts is set, else `count`.
template <class Acc>
struct Side {
  const Acc* hi;
  const Acc* lo;
  ptrdiff_t off_hi, off_lo;
  const int32_t* counts;
  int32_t count;
};

template <class Sum, class Acc>
inline Sum side_sum(const Side<Acc>& sd, ptrdiff_t c) {
  return static_cast<Sum>(sd.hi[c + sd.off_hi] - sd.lo[c + sd.off_lo]);
}

template <class Acc>
inline int32_t side_count(const Side<Acc>& sd, ptrdiff_t c) {
  return sd.counts ? sd.counts[c] : sd.count;
}

// (S, N) at column c from k sides in the fixed order, sides with no cell dropped; N = 0 if none.
template <class Sum, class Acc>
inline void select_scalar(CfarMethod method, const Side<Acc>* sides, int k, ptrdiff_t c, int64_t& s, int& n) {
  int64_t sums[4];
  int counts[4];
  int m = 0;
  for (int i = 0; i < k; ++i) {
    const int32_t cnt = side_count(sides[i], c);
    if (cnt <= 0) continue;
    sums[m] = side_sum<Sum>(sides[i], c);
    counts[m++] = cnt;
  }
  if (m == 0) {
    s = 0;
    n = 0;
    return;
  }
  choose(method, sums, counts, m, s, n);
}

enum class Reduce { kMin, kMax, kSum };

#if defined(__SSE2__)
constexpr bool kHaveSse2 = true;
#else
constexpr bool kHaveSse2 = false;
#endif

// Row kernels (cfar_row_kernels.cpp), instantiated for the (Pixel, Acc, Sum) the integer
// path uses: (uint8_t, uint32_t, int32_t) and (uint8_t or uint16_t, uint64_t, int64_t).

// Sides with equal counts: out[c] = min / max / total of the side sums, c in [c0, c1).
template <Reduce R, class Acc, class Sum>
void reduce_equal_sides(const Side<Acc>* sides, int k, ptrdiff_t c0, ptrdiff_t c1, Sum* out);

// Any counts: (S, N) per column into s_out / n_out, c in [c0, c1), exactly select_scalar.
// 4 columns at a time when the first side has cells in every column (SOCA / GOCA: then a
// side without cells, sum 0 and count 0, is never taken) and every cross product S_i N_j
// is below 2^24 (exact in float); the caller checks both.
template <class Acc, class Sum>
void select_sides(CfarMethod method, const Side<Acc>* sides, int k, bool vector_ok, ptrdiff_t c0, ptrdiff_t c1,
                  Sum* s_out, int32_t* n_out);

// next[c] = prev[c] + src[c], c in [0, n).
template <class Pixel, class Acc>
void add_row(const Acc* prev, const Pixel* src, Acc* next, size_t n);

// q[0] = 0, q[c + 1] = q[c] + line[c], c in [0, n).
template <class Pixel, class Acc>
void row_prefix(const Pixel* line, Acc* q, size_t n);

// Number of cells in line[0, n) above the integer gate g (0 <= g).
template <class Pixel>
size_t count_above(const Pixel* line, size_t n, int64_t g);

// The columns of line[0, n) above the integer gate g (0 <= g), in order, into cand (room
// for n + 4); returns their number.
template <class Pixel>
size_t columns_above(const Pixel* line, size_t n, int64_t g, int* cand);

// ---------------------------------------------------------------------------------------
// The 8-bit threshold table (cfar_threshold_table.cpp).
// smax[N][x] for 8-bit images, x in [0, 256): the largest S in [0, 255 N] for which x is a
// detection against a training sum S of N cells, -1 if there is none (always so at or
// below the gate). For α finite and >= 0 the rule is monotone in S: rhs = α S and both
// bounds grow with S, so "x N > upper bound" can only turn false and "x N < lower bound"
// only true as S grows, and between them fl(x N / S) only shrinks. So S <= smax[N][x] is
// the rule itself, and smax is found by evaluating the rule next to the estimate x N / α.
// Rows are built on first use and kept per thread for the last few (pfa, gate) pairs.
// S <= smax[N][x] as integer compares around a linear estimate T(x) = trunc(fl(x k)):
// for x above the gate, S <= T(x) + lo is a detection and S > T(x) + hi is not
// (smax - T spans [lo, hi], measured over every x when the row is built); only
// T + lo < S <= T + hi needs the table. Usually hi = lo, then the compare is exact.
struct Linear {
  bool ok = false;
  float k = 0;
  int32_t lo1 = 0, hi1 = 0;  // lo + 1, hi + 1
  int32_t x_gate = 0;        // x > x_gate: above the gate (and x >= 1)
  bool fits16 = false;       // T + lo1 and T + hi1 fit in int16 for every x
};

class ThresholdTable {
 public:
  // Rows 0 .. max_n must fit before any row pointer is taken; false if α is not finite
  // and >= 0 for some N <= max_n (the caller then evaluates the rule directly).
  bool prepare(int max_n) {
    if (max_n > checked_n_) {
      for (int n = checked_n_ + 1; n <= max_n; ++n) {
        const double a = cfar_alpha(n, pfa_);
        sane_ = sane_ && std::isfinite(a) && a >= 0.0;
        alpha_.push_back(a);
      }
      checked_n_ = max_n;
      table_.resize(static_cast<size_t>(max_n + 1) * 256, -1);
      linear_.resize(static_cast<size_t>(max_n) + 1);
      built_.resize(static_cast<size_t>(max_n) + 1, 0);
      built_[0] = 1;  // N = 0: no training cell, never a detection
    }
    return sane_;
  }

  const int32_t* row(int n) {
    const int32_t* r = table_.data() + static_cast<size_t>(n) * 256;
    if (!built_[static_cast<size_t>(n)]) build(n);
    return r;
  }

  // After row(n): a vector form of the same compare (see Linear).
  const Linear& linear(int n) const { return linear_[static_cast<size_t>(n)]; }

  bool matches(double pfa, int64_t gate) const {
    return used_ && std::memcmp(&pfa, &pfa_, sizeof pfa) == 0 && gate == gate_;
  }
  void reset(double pfa, int64_t gate) {
    *this = ThresholdTable{};
    pfa_ = pfa;
    gate_ = gate;
    used_ = true;
  }
  uint64_t last_use = 0;

 private:
  void build(int n);

  double pfa_ = 0;
  int64_t gate_ = 0;
  bool used_ = false;
  bool sane_ = true;
  int checked_n_ = 0;
  std::vector<double> alpha_{0.0};
  std::vector<int32_t> table_;
  std::vector<Linear> linear_;
  std::vector<uint8_t> built_;
};

// This thread's table for (pfa, gate): the last few pairs are kept, least recently used
// replaced.
ThresholdTable& threshold_table(double pfa, int64_t gate);

// ---------------------------------------------------------------------------------------
// The interior of an 8-bit row with equal counts (cfar_uniform_hits.cpp): the k sides
// reduced by R (min / max / total) and decided against smax with lin (Linear), 4 or, when
// `narrow` (every sum and T + lo1, T + hi1 fit in int16), 8 columns at a time; hit columns
// appended to cand in order (n_hits counts them). Returns the first column not done (the
// caller finishes [c, c1) with the table); c0 when SSE2 is not available.
ptrdiff_t uniform_hits(Reduce r, int k, bool narrow, const Side<uint32_t>* sides, ptrdiff_t c0, ptrdiff_t c1,
                       const uint8_t* line, const int32_t* smax, const Linear& lin, int* cand, size_t& n_hits);

}  // namespace orthosonar::perception::detail
