#include "core/perception/cfar.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace orthosonar::perception {
namespace {

// Keeps detections with at least `min_n` of their 8 neighbours detected (neighbours
// counted in the unfiltered set), using a rows x cols occupancy mask.
std::vector<Detection> filter_isolated(std::vector<Detection> dets, int min_n, int rows, int cols) {
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

// x > gate, exactly, in the pixel's own type: for integers x > gate <=> x > floor(gate).
int64_t integer_gate(double gate) {
  return static_cast<int64_t>(std::floor(std::clamp(gate, -1.0, 1e6)));
}

// SOCA / GOCA over the k non-empty sides in the fixed order (lead, lag, left, right):
// means s_i / n_i compared exactly by cross-multiplication, ties keep the first side.
// CA: all training cells. k > 0.
inline void choose(CfarMethod method, const int64_t* sums, const int* counts, int k, int64_t& s, int& n) {
  s = sums[0];
  n = counts[0];
  if (method == CfarMethod::kCa) {
    for (int i = 1; i < k; ++i) {
      s += sums[i];
      n += counts[i];
    }
  } else if (method == CfarMethod::kSoca) {
    for (int i = 1; i < k; ++i) {
      const bool take = sums[i] * n < s * counts[i];
      s = take ? sums[i] : s;
      n = take ? counts[i] : n;
    }
  } else {
    for (int i = 1; i < k; ++i) {
      const bool take = sums[i] * n > s * counts[i];
      s = take ? sums[i] : s;
      n = take ? counts[i] : n;
    }
  }
}

// ---------------------------------------------------------------------------------------
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
  std::vector<double> alpha(static_cast<size_t>(max_n) + 1, 0.0);
  for (int n = 1; n <= max_n; ++n) alpha[static_cast<size_t>(n)] = cfar_alpha(n, cfg.pfa);

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
      double s = sums[0];
      int n = counts[0];
      if (cfg.method == CfarMethod::kCa) {
        for (int i = 1; i < k; ++i) {
          s += sums[i];
          n += counts[i];
        }
      } else {
        const bool smallest = cfg.method == CfarMethod::kSoca;
        for (int i = 1; i < k; ++i) {
          const double a = sums[i] * static_cast<double>(n), b = s * static_cast<double>(counts[i]);
          if (smallest ? a < b : a > b) {
            s = sums[i];
            n = counts[i];
          }
        }
      }
      const double xn = static_cast<double>(x) * static_cast<double>(n);
      const bool hit = !(s > 0.0) ? static_cast<double>(x) > 0.0  // β = 0
                                  : ratio_test(xn, alpha[static_cast<size_t>(n)], s);
      if (hit) out.push_back({r, c, static_cast<float>(x)});
    }
  }
  return filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

// ---------------------------------------------------------------------------------------
// Integer images (8 and 16 bit). Sums are exact integers, so the order in which they are
// formed does not matter and a row can be processed as a whole:
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

// Sides with equal counts: out[c] = min / max / total of the side sums, c in [c0, c1).
template <Reduce R, class Acc, class Sum>
void reduce_equal_sides(const Side<Acc>* sides, int k, ptrdiff_t c0, ptrdiff_t c1, Sum* out) {
  ptrdiff_t c = c0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Acc, uint32_t> && std::is_same_v<Sum, int32_t>) {
    auto load = [](const uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
    auto diff = [&](const Side<Acc>& sd) { return _mm_sub_epi32(load(sd.hi + (c + sd.off_hi)), load(sd.lo + (c + sd.off_lo))); };
    for (; c + 4 <= c1; c += 4) {
      __m128i s = diff(sides[0]);
      for (int i = 1; i < k; ++i) {
        const __m128i d = diff(sides[i]);
        if constexpr (R == Reduce::kMin) {
          const __m128i gt = _mm_cmpgt_epi32(s, d);  // take d where s > d
          s = _mm_or_si128(_mm_and_si128(gt, d), _mm_andnot_si128(gt, s));
        } else if constexpr (R == Reduce::kMax) {
          const __m128i gt = _mm_cmpgt_epi32(d, s);
          s = _mm_or_si128(_mm_and_si128(gt, d), _mm_andnot_si128(gt, s));
        } else {
          s = _mm_add_epi32(s, d);
        }
      }
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + c), s);
    }
  }
#endif
  for (; c < c1; ++c) {
    Sum s = side_sum<Sum>(sides[0], c);
    for (int i = 1; i < k; ++i) {
      const Sum d = side_sum<Sum>(sides[i], c);
      if constexpr (R == Reduce::kMin) s = std::min(s, d);
      else if constexpr (R == Reduce::kMax) s = std::max(s, d);
      else s += d;
    }
    out[c] = s;
  }
}

// Any counts: (S, N) per column into s_out / n_out, c in [c0, c1), exactly select_scalar.
// 4 columns at a time when the first side has cells in every column (SOCA / GOCA: then a
// side without cells, sum 0 and count 0, is never taken) and every cross product S_i N_j
// is below 2^24 (exact in float); the caller checks both.
template <class Acc, class Sum>
void select_sides(CfarMethod method, const Side<Acc>* sides, int k, bool vector_ok, ptrdiff_t c0, ptrdiff_t c1,
                  Sum* s_out, int32_t* n_out) {
  ptrdiff_t c = c0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Acc, uint32_t> && std::is_same_v<Sum, int32_t>) {
    if (vector_ok) {
      auto load_u = [](const uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
      auto load_i = [](const int32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
      auto blend = [](__m128i mask, __m128i a, __m128i b) {
        return _mm_or_si128(_mm_and_si128(mask, a), _mm_andnot_si128(mask, b));
      };
      const bool ca = method == CfarMethod::kCa, soca = method == CfarMethod::kSoca;
      for (; c + 4 <= c1; c += 4) {
        auto sum = [&](const Side<Acc>& sd) { return _mm_sub_epi32(load_u(sd.hi + (c + sd.off_hi)), load_u(sd.lo + (c + sd.off_lo))); };
        auto cnt = [&](const Side<Acc>& sd) { return sd.counts ? load_i(sd.counts + c) : _mm_set1_epi32(sd.count); };
        __m128i s = sum(sides[0]), n = cnt(sides[0]);
        for (int i = 1; i < k; ++i) {
          const __m128i si = sum(sides[i]), ni = cnt(sides[i]);
          if (ca) {
            s = _mm_add_epi32(s, si);
            n = _mm_add_epi32(n, ni);
          } else {
            const __m128 a = _mm_mul_ps(_mm_cvtepi32_ps(si), _mm_cvtepi32_ps(n));
            const __m128 b = _mm_mul_ps(_mm_cvtepi32_ps(s), _mm_cvtepi32_ps(ni));
            const __m128i take = _mm_castps_si128(soca ? _mm_cmplt_ps(a, b) : _mm_cmpgt_ps(a, b));
            s = blend(take, si, s);
            n = blend(take, ni, n);
          }
        }
        _mm_storeu_si128(reinterpret_cast<__m128i*>(s_out + c), s);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(n_out + c), n);
      }
    }
  }
#endif
  (void)vector_ok;
  for (; c < c1; ++c) {
    int64_t s;
    int n;
    select_scalar<Sum>(method, sides, k, c, s, n);
    s_out[c] = static_cast<Sum>(s);
    n_out[c] = n;
  }
}

// next[c] = prev[c] + src[c], c in [0, n).
template <class Pixel, class Acc>
void add_row(const Acc* prev, const Pixel* src, Acc* next, size_t n) {
  size_t c = 0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t>) {
    const __m128i zero = _mm_setzero_si128();
    auto load = [](const uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
    auto store = [](uint32_t* p, __m128i v) { _mm_storeu_si128(reinterpret_cast<__m128i*>(p), v); };
    for (; c + 16 <= n; c += 16) {
      const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + c));
      const __m128i lo = _mm_unpacklo_epi8(b, zero), hi = _mm_unpackhi_epi8(b, zero);
      store(next + c, _mm_add_epi32(load(prev + c), _mm_unpacklo_epi16(lo, zero)));
      store(next + c + 4, _mm_add_epi32(load(prev + c + 4), _mm_unpackhi_epi16(lo, zero)));
      store(next + c + 8, _mm_add_epi32(load(prev + c + 8), _mm_unpacklo_epi16(hi, zero)));
      store(next + c + 12, _mm_add_epi32(load(prev + c + 12), _mm_unpackhi_epi16(hi, zero)));
    }
  }
#endif
  for (; c < n; ++c) next[c] = prev[c] + static_cast<Acc>(src[c]);
}

// q[0] = 0, q[c + 1] = q[c] + line[c], c in [0, n).
template <class Pixel, class Acc>
void row_prefix(const Pixel* line, Acc* q, size_t n) {
  q[0] = 0;
  size_t c = 0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t>) {
    // 8 cells at a time: their prefix sums in 16 bits (at most 8 * 255), widened, plus
    // the running total (a single add on the loop-carried path).
    const __m128i zero = _mm_setzero_si128();
    __m128i carry = zero;
    for (; c + 8 <= n; c += 8) {
      __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(line + c)), zero);
      v = _mm_add_epi16(v, _mm_slli_si128(v, 2));
      v = _mm_add_epi16(v, _mm_slli_si128(v, 4));
      v = _mm_add_epi16(v, _mm_slli_si128(v, 8));
      const __m128i lo = _mm_unpacklo_epi16(v, zero), hi = _mm_unpackhi_epi16(v, zero);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(q + c + 1), _mm_add_epi32(lo, carry));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(q + c + 5), _mm_add_epi32(hi, carry));
      carry = _mm_add_epi32(carry, _mm_shuffle_epi32(hi, 0xFF));
    }
  }
#endif
  for (; c < n; ++c) q[c + 1] = q[c] + static_cast<Acc>(line[c]);
}

// Number of cells in line[0, n) above the integer gate g (0 <= g).
template <class Pixel>
size_t count_above(const Pixel* line, size_t n, int64_t g) {
  size_t count = 0, c = 0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Pixel, uint8_t>) {
    if (g < 255) {
      // x > g <=> max(x, g + 1) == x; the 0xFF bytes are counted by a sum of absolute
      // differences against zero (255 per hit).
      const __m128i g1 = _mm_set1_epi8(static_cast<char>(static_cast<uint8_t>(g + 1)));
      __m128i total = _mm_setzero_si128();
      for (; c + 16 <= n; c += 16) {
        const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(line + c));
        const __m128i hit = _mm_cmpeq_epi8(_mm_max_epu8(x, g1), x);
        total = _mm_add_epi64(total, _mm_sad_epu8(hit, _mm_setzero_si128()));
      }
      uint64_t parts[2];
      _mm_storeu_si128(reinterpret_cast<__m128i*>(parts), total);
      count = static_cast<size_t>((parts[0] + parts[1]) / 255u);
    }
  }
#endif
  for (; c < n; ++c) count += static_cast<int64_t>(line[c]) > g ? 1u : 0u;
  return count;
}

// The columns of line[0, n) above the integer gate g (0 <= g), in order, into cand (room
// for n + 4); returns their number. 8-bit: 16 cells per compare, then the set bits (a row
// that takes this path has few cells above the gate).
template <class Pixel>
size_t columns_above(const Pixel* line, size_t n, int64_t g, int* cand) {
  size_t m = 0, c = 0;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<Pixel, uint8_t>) {
    if (g >= 0 && g < 255) {
      const __m128i g1 = _mm_set1_epi8(static_cast<char>(static_cast<uint8_t>(g + 1)));
      for (; c + 16 <= n; c += 16) {
        const __m128i x = _mm_loadu_si128(reinterpret_cast<const __m128i*>(line + c));
        auto bits = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(x, g1), x)));
        while (bits != 0) {
          cand[m++] = static_cast<int>(c) + std::countr_zero(bits);
          bits &= bits - 1;
        }
      }
    }
  }
#endif
  for (; c < n; ++c) {
    cand[m] = static_cast<int>(c);
    m += static_cast<int64_t>(line[c]) > g ? 1u : 0u;
  }
  return m;
}

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
  void build(int n) {
    built_[static_cast<size_t>(n)] = 1;
    int32_t* row = table_.data() + static_cast<size_t>(n) * 256;
    const double a = alpha_[static_cast<size_t>(n)];
    const int64_t cap = 255 * static_cast<int64_t>(n);
    for (int64_t x = 1; x < 256; ++x) {  // x = 0 is never a detection for α >= 0
      if (x <= gate_) continue;
      const double lhs = static_cast<double>(x * n);
      auto hit = [&](int64_t s) { return s == 0 || ratio_test(lhs, a, static_cast<double>(s)); };  // S = 0: x > 0
      int64_t s = cap;
      if (a > 0.0) s = static_cast<int64_t>(std::floor(std::min(lhs / a, static_cast<double>(cap))));
      if (hit(s)) {
        while (s < cap && hit(s + 1)) ++s;
      } else {
        while (!hit(s)) --s;  // hit(0)
      }
      row[x] = static_cast<int32_t>(s);
    }
    // T(x) = trunc(fl(x k)), k = fl(N / α), evaluated exactly as the vector code does;
    // smax[N][x] - T(x) over the cells above the gate spans [lo, hi].
    Linear& lin = linear_[static_cast<size_t>(n)];
    lin = Linear{};
    const int64_t x_first = std::max<int64_t>(gate_ + 1, 1);
    if (a > 0.0 && x_first <= 255 && static_cast<double>(n) / a * 255.0 < 8388608.0) {
      lin.k = static_cast<float>(static_cast<double>(n) / a);
      int64_t lo = cap + 1, hi = -cap - 1, t_max = 0;
      for (int64_t x = 0; x < 256; ++x) {
        const auto t = static_cast<int64_t>(static_cast<int32_t>(static_cast<float>(x) * lin.k));
        t_max = std::max(t_max, t);
        if (x < x_first) continue;
        lo = std::min(lo, row[x] - t);
        hi = std::max(hi, row[x] - t);
      }
      lin.fits16 = t_max + std::max<int64_t>(hi + 1, 0) <= 32767 && lo + 1 >= -32768 && t_max <= 32767;
      lin.lo1 = static_cast<int32_t>(lo + 1);
      lin.hi1 = static_cast<int32_t>(hi + 1);
      lin.x_gate = static_cast<int32_t>(x_first - 1);
      lin.ok = true;
    }
  }

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


#if defined(__SSE2__)
// Lane indices of the set bits of a 4-bit mask, in order, and their number.
alignas(16) constexpr int32_t kLanes[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0}, {1, 2, 0, 0}, {0, 1, 2, 0},
    {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0}, {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};
constexpr uint8_t kBits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// 8-bit interior with equal counts: K sides reduced (min / max / total) and decided
// against the row of thresholds, 4 columns at a time; hit columns appended to cand in
// order. Returns the first column not done (the caller finishes [c, c1) with the table).
template <Reduce R, int K>
ptrdiff_t uniform_hits(const Side<uint32_t>* sides, ptrdiff_t c0, ptrdiff_t c1, const uint8_t* line,
                       const int32_t* smax, const Linear& lin, int* cand, size_t& n_hits) {
  const uint32_t* hi[K];
  const uint32_t* lo[K];
  for (int i = 0; i < K; ++i) {
    hi[i] = sides[i].hi + sides[i].off_hi;
    lo[i] = sides[i].lo + sides[i].off_lo;
  }
  auto load = [](const uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
  const __m128i zero = _mm_setzero_si128(), lo1 = _mm_set1_epi32(lin.lo1), hi1 = _mm_set1_epi32(lin.hi1);
  const __m128i x_gate = _mm_set1_epi32(lin.x_gate);
  const __m128 k = _mm_set1_ps(lin.k);
  const bool exact = lin.lo1 == lin.hi1;
  size_t n = n_hits;
  ptrdiff_t c = c0;
  for (; c + 4 <= c1; c += 4) {
    __m128i s = _mm_sub_epi32(load(hi[0] + c), load(lo[0] + c));
    for (int i = 1; i < K; ++i) {
      const __m128i d = _mm_sub_epi32(load(hi[i] + c), load(lo[i] + c));
      if constexpr (R == Reduce::kMin) {
        const __m128i gt = _mm_cmpgt_epi32(s, d);
        s = _mm_or_si128(_mm_and_si128(gt, d), _mm_andnot_si128(gt, s));
      } else if constexpr (R == Reduce::kMax) {
        const __m128i gt = _mm_cmpgt_epi32(d, s);
        s = _mm_or_si128(_mm_and_si128(gt, d), _mm_andnot_si128(gt, s));
      } else {
        s = _mm_add_epi32(s, d);
      }
    }
    uint32_t w;
    std::memcpy(&w, line + c, 4);
    const __m128i x = _mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(static_cast<int>(w)), zero), zero);
    const __m128i t = _mm_cvttps_epi32(_mm_mul_ps(_mm_cvtepi32_ps(x), k));
    const __m128i above = _mm_cmpgt_epi32(x, x_gate);
    int mask = _mm_movemask_ps(_mm_castsi128_ps(_mm_and_si128(above, _mm_cmpgt_epi32(_mm_add_epi32(t, lo1), s))));
    if (!exact) {
      const __m128i maybe = _mm_and_si128(above, _mm_cmpgt_epi32(_mm_add_epi32(t, hi1), s));
      int unsure = _mm_movemask_ps(_mm_castsi128_ps(maybe)) & ~mask;
      if (unsure) {
        alignas(16) int32_t sv[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(sv), s);
        for (int j = 0; j < 4; ++j)
          if (((unsure >> j) & 1) && sv[j] <= smax[line[c + j]]) mask |= 1 << j;
      }
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cand + n),
                     _mm_add_epi32(_mm_set1_epi32(static_cast<int>(c)),
                                   _mm_load_si128(reinterpret_cast<const __m128i*>(kLanes[mask]))));
    n += kBits[mask];
  }
  n_hits = n;
  return c;
}

// The same with 16-bit lanes, 8 columns at a time: every side sum and the total are at
// most 255 N <= 32767 (the caller checks), T + lo1 and T + hi1 fit (Linear::fits16).
template <Reduce R, int K>
ptrdiff_t uniform_hits16(const Side<uint32_t>* sides, ptrdiff_t c0, ptrdiff_t c1, const uint8_t* line,
                         const int32_t* smax, const Linear& lin, int* cand, size_t& n_hits) {
  const uint32_t* hi[K];
  const uint32_t* lo[K];
  for (int i = 0; i < K; ++i) {
    hi[i] = sides[i].hi + sides[i].off_hi;
    lo[i] = sides[i].lo + sides[i].off_lo;
  }
  auto load = [](const uint32_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); };
  const __m128i zero = _mm_setzero_si128();
  const __m128i lo1 = _mm_set1_epi16(static_cast<int16_t>(lin.lo1)), hi1 = _mm_set1_epi16(static_cast<int16_t>(lin.hi1));
  const __m128i x_gate = _mm_set1_epi16(static_cast<int16_t>(lin.x_gate));
  const __m128 k = _mm_set1_ps(lin.k);
  const bool exact = lin.lo1 == lin.hi1;
  size_t n = n_hits;
  ptrdiff_t c = c0;
  for (; c + 8 <= c1; c += 8) {
    __m128i a = _mm_sub_epi32(load(hi[0] + c), load(lo[0] + c));
    __m128i b = _mm_sub_epi32(load(hi[0] + c + 4), load(lo[0] + c + 4));
    __m128i s;
    if constexpr (R == Reduce::kSum) {
      for (int i = 1; i < K; ++i) {
        a = _mm_add_epi32(a, _mm_sub_epi32(load(hi[i] + c), load(lo[i] + c)));
        b = _mm_add_epi32(b, _mm_sub_epi32(load(hi[i] + c + 4), load(lo[i] + c + 4)));
      }
      s = _mm_packs_epi32(a, b);
    } else {
      s = _mm_packs_epi32(a, b);
      for (int i = 1; i < K; ++i) {
        const __m128i d = _mm_packs_epi32(_mm_sub_epi32(load(hi[i] + c), load(lo[i] + c)),
                                          _mm_sub_epi32(load(hi[i] + c + 4), load(lo[i] + c + 4)));
        s = R == Reduce::kMin ? _mm_min_epi16(s, d) : _mm_max_epi16(s, d);
      }
    }
    const __m128i x = _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(line + c)), zero);
    const __m128i t_lo = _mm_cvttps_epi32(_mm_mul_ps(_mm_cvtepi32_ps(_mm_unpacklo_epi16(x, zero)), k));
    const __m128i t_hi = _mm_cvttps_epi32(_mm_mul_ps(_mm_cvtepi32_ps(_mm_unpackhi_epi16(x, zero)), k));
    const __m128i t = _mm_packs_epi32(t_lo, t_hi);
    const __m128i above = _mm_cmpgt_epi16(x, x_gate);
    const __m128i hit = _mm_and_si128(above, _mm_cmpgt_epi16(_mm_add_epi16(t, lo1), s));
    int mask = _mm_movemask_epi8(_mm_packs_epi16(hit, zero));
    if (!exact) {
      const __m128i maybe = _mm_and_si128(above, _mm_cmpgt_epi16(_mm_add_epi16(t, hi1), s));
      const int unsure = _mm_movemask_epi8(_mm_packs_epi16(maybe, zero)) & ~mask;
      if (unsure) {
        alignas(16) int16_t sv[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(sv), s);
        for (int j = 0; j < 8; ++j)
          if (((unsure >> j) & 1) && sv[j] <= smax[line[c + j]]) mask |= 1 << j;
      }
    }
    const int m0 = mask & 15, m1 = mask >> 4;
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cand + n),
                     _mm_add_epi32(_mm_set1_epi32(static_cast<int>(c)),
                                   _mm_load_si128(reinterpret_cast<const __m128i*>(kLanes[m0]))));
    n += kBits[m0];
    _mm_storeu_si128(reinterpret_cast<__m128i*>(cand + n),
                     _mm_add_epi32(_mm_set1_epi32(static_cast<int>(c + 4)),
                                   _mm_load_si128(reinterpret_cast<const __m128i*>(kLanes[m1]))));
    n += kBits[m1];
  }
  n_hits = n;
  return c;
}
#endif

ThresholdTable& threshold_table(double pfa, int64_t gate) {
  thread_local ThresholdTable tables[4];
  thread_local uint64_t clock = 0;
  ThresholdTable* pick = &tables[0];
  for (ThresholdTable& t : tables) {
    if (t.matches(pfa, gate)) {
      pick = &t;
      break;
    }
    if (t.last_use < pick->last_use) pick = &t;
  }
  if (!pick->matches(pfa, gate)) pick->reset(pfa, gate);
  pick->last_use = ++clock;
  return *pick;
}

template <class Pixel, class Acc, class Sum>
class IntegerCfar {
 public:
  IntegerCfar(const Pixel* img, int rows, int cols, const CfarConfig& cfg, int64_t gate)
      : img_(img), rows_(rows), cols_(cols), C_(static_cast<size_t>(cols)), cfg_(cfg), gate_(gate) {
    // Extents beyond the image change nothing: clamp g and t to its size (along bearing,
    // to its width).
    const int64_t dim = std::max(rows, cols);
    g_ = std::min<int64_t>(cfg.guard_cells, dim);
    t_ = std::min<int64_t>(cfg.train_cells, dim);
    gb_ = std::min<int64_t>(cfg.guard_cells, cols);
    tb_ = std::min<int64_t>(cfg.train_cells, cols);
    cross_ = cfg.window == CfarWindow::kCross;
    const int64_t n_sides = cross_ ? 4 : 2;
    max_n_ = static_cast<int>(cfg.method == CfarMethod::kCa ? n_sides * t_ : t_);
    if constexpr (std::is_same_v<Pixel, uint8_t>) {
      if (max_n_ <= 4096) {
        table_ = &threshold_table(cfg.pfa, gate);
        if (!table_->prepare(max_n_)) table_ = nullptr;
      }
    }
    if (!table_) {
      alpha_.assign(static_cast<size_t>(max_n_) + 1, 0.0);
      for (int n = 1; n <= max_n_; ++n) alpha_[static_cast<size_t>(n)] = cfar_alpha(n, cfg.pfa);
    }
    // Vector selection: every cross product S_i N_j below 2^24 (S <= 255 t, N <= t).
    vector_ok_ = 255 * t_ * t_ < (int64_t{1} << 24);
    // Ring of column prefix sums: P between a cell's window ends (2(g + t) + 1 rows apart).
    K_ = static_cast<size_t>(std::min<int64_t>(2 * (g_ + t_) + 2, static_cast<int64_t>(rows) + 1));
    ring_.assign(K_ * C_, Acc{0});
    // Row prefix sums, padded: qpad_[pad_ + p] = Q[clamp(p, 0, cols)], so that a bearing
    // side's sum is one difference in every column, empty or truncated sides included.
    pad_ = static_cast<size_t>(gb_ + tb_ + 1);
    qpad_.assign(C_ + 2 * pad_ + 4, Acc{0});
    if (cross_) {
      counts_left_.resize(C_ + 4);
      counts_right_.resize(C_ + 4);
      for (int64_t c = 0; c < cols; ++c) {
        counts_left_[static_cast<size_t>(c)] = static_cast<int32_t>(std::clamp<int64_t>(c - gb_, 0, tb_));
        counts_right_[static_cast<size_t>(c)] = static_cast<int32_t>(std::clamp<int64_t>(cols - (c + gb_ + 1), 0, tb_));
      }
    }
    red_.assign(C_ + 4, Sum{0});
    nsel_.assign(C_ + 4, 0);
    cand_.assign(C_ + 4, 0);
    row_hits_.assign(static_cast<size_t>(rows), 0);
  }

  std::vector<Detection> run() {
    std::vector<Detection> out;
    if (gate_ >= static_cast<int64_t>(std::numeric_limits<Pixel>::max())) return out;
    size_t computed = 0;  // P_0 .. P_computed are in the ring
    for (int r = 0; r < rows_; ++r) {
      const int64_t R = r;
      const auto target = static_cast<size_t>(std::min<int64_t>(rows_, R + g_ + 1 + t_));
      while (computed < target) {  // P_{i+1} = P_i + row i
        add_row(prefix_row(computed), img_ + computed * C_, prefix_row(computed + 1), C_);
        ++computed;
      }
      line_ = img_ + static_cast<size_t>(r) * C_;
      const size_t n_above = gate_ < 0 ? C_ : count_above(line_, C_, gate_);
      if (n_above == 0) continue;
      // The sides in the fixed order; range counts depend on the row only.
      k_ = 0;
      const int nl = static_cast<int>(std::clamp<int64_t>(R - g_, 0, t_));
      const int ng = static_cast<int>(std::clamp<int64_t>(rows_ - (R + g_ + 1), 0, t_));
      if (nl > 0)
        sides_[k_++] = {prefix_row(static_cast<size_t>(R - g_)), prefix_row(static_cast<size_t>(R - g_ - nl)), 0, 0, nullptr, nl};
      if (ng > 0)
        sides_[k_++] = {prefix_row(static_cast<size_t>(R + g_ + 1 + ng)), prefix_row(static_cast<size_t>(R + g_ + 1)), 0, 0, nullptr, ng};
      first_bearing_ = k_;
      if (cross_) {
        const auto pad = static_cast<ptrdiff_t>(pad_), g = static_cast<ptrdiff_t>(gb_), t = static_cast<ptrdiff_t>(tb_);
        sides_[k_++] = {qpad_.data(), qpad_.data(), pad - g, pad - g - t, counts_left_.data(), 0};
        sides_[k_++] = {qpad_.data(), qpad_.data(), pad + g + 1 + t, pad + g + 1, counts_right_.data(), 0};
      }
      if (k_ == 0) continue;  // no training cell anywhere in this row
      size_t n_hits;
      if (n_above * 16 >= C_) {
        if (cross_) bearing_prefix();
        n_hits = dense_row(nl, ng);
      } else {
        // Few cells above the gate: test only those (bearing sums directly when cheaper).
        const size_t n_cand = columns_above(line_, C_, gate_, cand_.data());
        const bool prefix = cross_ && static_cast<int64_t>(n_cand) * 2 * tb_ > static_cast<int64_t>(C_);
        if (prefix) bearing_prefix();
        n_hits = 0;
        for (size_t i = 0; i < n_cand; ++i) {
          const int c = cand_[i];
          int64_t s;
          int n;
          if (prefix) {
            select_scalar<Sum>(cfg_.method, sides_, k_, c, s, n);
          } else {
            select_direct(c, s, n);
          }
          cand_[n_hits] = c;
          n_hits += decide(line_[c], s, n) ? 1u : 0u;
        }
      }
      row_hits_[static_cast<size_t>(r)] = n_hits;
      append_hits(n_hits);
    }
    // One allocation of the exact size: growing a large vector hit by hit costs more than
    // the whole test (each reallocation touches fresh pages).
    size_t total = 0;
    for (size_t n : row_hits_) total += n;
    out.reserve(total);
    size_t block = 0, pos = 0;
    for (int r = 0; r < rows_; ++r) {
      const Pixel* line = img_ + static_cast<size_t>(r) * C_;
      for (size_t i = 0; i < row_hits_[static_cast<size_t>(r)]; ++i) {
        if (pos == kBlock) {
          ++block;
          pos = 0;
        }
        const int c = blocks_[block][pos++];
        out.push_back({r, c, static_cast<float>(line[c])});
      }
    }
    return out;
  }

 private:
  Acc* prefix_row(size_t i) { return ring_.data() + (i % K_) * C_; }

  void bearing_prefix() {
    Acc* q = qpad_.data() + pad_;
    row_prefix(line_, q, C_);
    std::fill(qpad_.data(), q, Acc{0});
    std::fill(q + C_ + 1, q + C_ + 1 + pad_, q[C_]);
  }

  // select_scalar at column c with the bearing sums added up directly (a few cells).
  void select_direct(int c, int64_t& s, int& n) const {
    int64_t sums[4];
    int counts[4];
    int m = 0;
    for (int i = 0; i < first_bearing_; ++i) {
      sums[m] = side_sum<Sum>(sides_[i], c);
      counts[m++] = sides_[i].count;
    }
    if (cross_) {
      const int64_t C = c;
      const int64_t ranges[2][2] = {{std::max<int64_t>(0, C - gb_ - tb_), C - gb_},
                                    {C + gb_ + 1, std::min<int64_t>(cols_, C + gb_ + 1 + tb_)}};
      for (const auto& rg : ranges) {
        if (rg[1] <= rg[0]) continue;
        int64_t sum = 0;
        for (int64_t i = rg[0]; i < rg[1]; ++i) sum += line_[i];
        sums[m] = sum;
        counts[m++] = static_cast<int>(rg[1] - rg[0]);
      }
    }
    if (m == 0) {
      s = 0;
      n = 0;
      return;
    }
    choose(cfg_.method, sums, counts, m, s, n);
  }

  bool decide(Pixel x, int64_t s, int n) {
    if (table_) return s <= static_cast<int64_t>(table_->row(n)[x]);
    if (n == 0 || !(static_cast<int64_t>(x) > gate_)) return false;
    if (!(s > 0)) return x > 0;  // β = 0
    return ratio_test(static_cast<double>(static_cast<int64_t>(x) * n), alpha_[static_cast<size_t>(n)],
                      static_cast<double>(s));
  }

  // Every column of the current row; hits go to cand_ in column order.
  size_t dense_row(int nl, int ng) {
    // Interior columns [c0, c1): both bearing sides full (cross), or all columns (range).
    int64_t c0 = 0, c1 = cols_;
    if (cross_) {
      c0 = std::min<int64_t>(gb_ + tb_, cols_);
      c1 = std::max<int64_t>(c0, cols_ - gb_ - tb_);
    }
    // There every side has a constant count: nl, ng, t, t. With CA, or with equal counts
    // (SOCA / GOCA compare means as sums; equal sums are the same (S, N)), one (S, N).
    const int t = static_cast<int>(tb_);
    int counts[4], k = 0, n_total = 0;
    if (nl > 0) counts[k++] = nl;
    if (ng > 0) counts[k++] = ng;
    if (cross_) {
      counts[k++] = t;
      counts[k++] = t;
    }
    bool uniform = c1 > c0;
    for (int i = 0; i < k; ++i) {
      n_total += counts[i];
      uniform = uniform && (cfg_.method == CfarMethod::kCa || counts[i] == counts[0]);
    }
    const int n_uniform = cfg_.method == CfarMethod::kCa ? n_total : counts[0];
    n_uniform_ = n_uniform;
    if (!uniform) c0 = c1 = cols_;

    Sum* red = red_.data();
    int32_t* nsel = nsel_.data();
    const bool fused = uniform && table_ && table_->row(n_uniform) && table_->linear(n_uniform).ok &&
                       std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t> && kHaveSse2;
    // Columns outside [c0, c1): any counts.
    const bool vec = cfg_.method == CfarMethod::kCa || (vector_ok_ && first_bearing_ > 0);
    select_sides(cfg_.method, sides_, k_, vec, 0, c0, red, nsel);
    select_sides(cfg_.method, sides_, k_, vec, c1, cols_, red, nsel);
    if (!fused) {
      switch (cfg_.method) {
        case CfarMethod::kSoca: reduce_equal_sides<Reduce::kMin>(sides_, k_, c0, c1, red); break;
        case CfarMethod::kGoca: reduce_equal_sides<Reduce::kMax>(sides_, k_, c0, c1, red); break;
        case CfarMethod::kCa: reduce_equal_sides<Reduce::kSum>(sides_, k_, c0, c1, red); break;
      }
    }
    size_t n_hits = 0;
    auto decide_range = [&](int64_t lo, int64_t hi) {
      for (int64_t c = lo; c < hi; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += decide(line_[c], red[c], nsel[c]) ? 1u : 0u;
      }
    };
    decide_range(0, c0);
    if (table_) {
      const int32_t* smax = table_->row(n_uniform);
      if (fused) {
        const int64_t done = fused_uniform(c0, c1, smax, n_hits);
        // The rest (< 4 columns) with the table, from the sums.
        switch (cfg_.method) {
          case CfarMethod::kSoca: reduce_equal_sides<Reduce::kMin>(sides_, k_, done, c1, red); break;
          case CfarMethod::kGoca: reduce_equal_sides<Reduce::kMax>(sides_, k_, done, c1, red); break;
          case CfarMethod::kCa: reduce_equal_sides<Reduce::kSum>(sides_, k_, done, c1, red); break;
        }
        c0 = done;
      }
      for (int64_t c = c0; c < c1; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += red[c] <= smax[line_[c]] ? 1u : 0u;
      }
    } else {
      for (int64_t c = c0; c < c1; ++c) {
        cand_[n_hits] = static_cast<int>(c);
        n_hits += decide(line_[c], red[c], n_uniform) ? 1u : 0u;
      }
    }
    decide_range(c1, cols_);
    return n_hits;
  }

  // The interior of an 8-bit row with equal counts, 4 columns at a time (uniform_hits).
  int64_t fused_uniform(int64_t c0, int64_t c1, const int32_t* smax, size_t& n_hits) {
#if defined(__SSE2__)
    if constexpr (std::is_same_v<Pixel, uint8_t> && std::is_same_v<Acc, uint32_t>) {
      const Linear& lin = table_->linear(n_uniform_);
      const bool narrow = lin.fits16 && 255 * n_uniform_ <= 32767;
      auto run_k = [&](auto r) -> int64_t {
        constexpr Reduce R = decltype(r)::value;
        if (narrow) {
          switch (k_) {
            case 1: return uniform_hits16<R, 1>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
            case 2: return uniform_hits16<R, 2>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
            case 3: return uniform_hits16<R, 3>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
            default: return uniform_hits16<R, 4>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
          }
        }
        switch (k_) {
          case 1: return uniform_hits<R, 1>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
          case 2: return uniform_hits<R, 2>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
          case 3: return uniform_hits<R, 3>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
          default: return uniform_hits<R, 4>(sides_, c0, c1, line_, smax, lin, cand_.data(), n_hits);
        }
      };
      switch (cfg_.method) {
        case CfarMethod::kSoca: return run_k(std::integral_constant<Reduce, Reduce::kMin>{});
        case CfarMethod::kGoca: return run_k(std::integral_constant<Reduce, Reduce::kMax>{});
        case CfarMethod::kCa: return run_k(std::integral_constant<Reduce, Reduce::kSum>{});
      }
    }
#endif
    (void)c1;
    (void)smax;
    (void)n_hits;
    return c0;
  }

  // Hit columns of every row, in blocks of kBlock (no reallocation, no copies).
  void append_hits(size_t n) {
    const int* src = cand_.data();
    while (n > 0) {
      if (blocks_.empty() || blocks_.back().size() == kBlock) {
        blocks_.emplace_back();
        blocks_.back().reserve(kBlock);
      }
      std::vector<int>& b = blocks_.back();
      const size_t take = std::min(n, kBlock - b.size());
      b.insert(b.end(), src, src + take);
      src += take;
      n -= take;
    }
  }

  const Pixel* img_;
  int rows_, cols_;
  size_t C_;
  const CfarConfig& cfg_;
  int64_t gate_;
  int64_t g_ = 0, t_ = 0, gb_ = 0, tb_ = 0;
  bool cross_ = true;
  int max_n_ = 0;
  ThresholdTable* table_ = nullptr;  // 8-bit images with α finite and >= 0
  std::vector<double> alpha_;        // otherwise
  bool vector_ok_ = false;
  size_t K_ = 1, pad_ = 1;
  std::vector<Acc> ring_, qpad_;
  std::vector<int32_t> counts_left_, counts_right_;
  std::vector<Sum> red_;
  std::vector<int32_t> nsel_;
  std::vector<int> cand_;
  static constexpr size_t kBlock = 8192;
  std::vector<std::vector<int>> blocks_;
  std::vector<size_t> row_hits_;
  // Current row.
  const Pixel* line_ = nullptr;
  Side<Acc> sides_[4];
  int k_ = 0, first_bearing_ = 0, n_uniform_ = 0;
};

template <class Pixel>
std::vector<Detection> detect_integer(const Pixel* img, int rows, int cols, const CfarConfig& cfg) {
  if (rows <= 0 || cols <= 0 || cfg.train_cells <= 0 || cfg.guard_cells < 0) return {};
  const int64_t gate = integer_gate(cfg.gate);
  std::vector<Detection> out;
  // 32-bit sums when every sum of up to 4 sides fits in int32 (any realistic 8-bit image).
  const int64_t t = std::min<int64_t>(cfg.train_cells, std::max(rows, cols));
  bool done = false;
  if constexpr (std::is_same_v<Pixel, uint8_t>) {
    if (4 * 255 * t < (int64_t{1} << 31)) {
      out = IntegerCfar<Pixel, uint32_t, int32_t>(img, rows, cols, cfg, gate).run();
      done = true;
    }
  }
  if (!done) out = IntegerCfar<Pixel, uint64_t, int64_t>(img, rows, cols, cfg, gate).run();
  return filter_isolated(std::move(out), cfg.min_neighbours, rows, cols);
}

}  // namespace

double cfar_alpha(int n_train, double pfa) {
  const double n = static_cast<double>(n_train);
  return n * (std::pow(pfa, -1.0 / n) - 1.0);
}

std::vector<Detection> cfar_detect(const SonarPing& ping, const CfarConfig& config) {
  const int rows = ping.rows, cols = ping.cols;
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (ping.bytes_per_pixel == 1) {
    if (ping.image.size() < n) return {};
    return detect_integer<uint8_t>(ping.image.data(), rows, cols, config);
  }
  if (ping.image.size() < 2 * n) return {};
  std::vector<uint16_t> wide(n);
  for (size_t i = 0; i < n; ++i)
    wide[i] = static_cast<uint16_t>(ping.image[2 * i] | (ping.image[2 * i + 1] << 8));
  return detect_integer<uint16_t>(wide.data(), rows, cols, config);
}

std::vector<Detection> cfar_detect(const float* image, int rows, int cols, const CfarConfig& config) {
  return detect_float(image, rows, cols, config);
}

const char* to_string(CfarMethod m) {
  switch (m) {
    case CfarMethod::kSoca: return "soca";
    case CfarMethod::kCa: return "ca";
    case CfarMethod::kGoca: return "goca";
  }
  return "?";
}

const char* to_string(CfarWindow w) {
  switch (w) {
    case CfarWindow::kCross: return "cross";
    case CfarWindow::kRange: return "range";
  }
  return "?";
}

}  // namespace orthosonar::perception
