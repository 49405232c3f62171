// The fused 8-bit SSE2 decision for a row's interior: side sums reduced and compared
// with the threshold table's linear estimate, 4 (32-bit lanes) or 8 (16-bit lanes)
// columns at a time.
#include <cstdint>
#include <cstring>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception::detail {

#if defined(__SSE2__)
namespace {

// Lane indices of the set bits of a 4-bit mask, in order, and their number.
alignas(16) constexpr int32_t kLanes[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0}, {1, 2, 0, 0}, {0, 1, 2, 0},
    {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0}, {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};
constexpr uint8_t kBits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// 8-bit interior with equal counts: K sides reduced (min / max / total) and decided
// against the row of thresholds, 4 columns at a time; hit columns appended to cand in
// order. Returns the first column not done (the caller finishes [c, c1) with the table).
template <Reduce R, int K>
ptrdiff_t uniform_hits4(const Side<uint32_t>* sides, ptrdiff_t c0, ptrdiff_t c1, const uint8_t* line,
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

// uniform_hits4 with 16-bit lanes, 8 columns at a time: every side sum and the total are at
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

}  // namespace
#endif

ptrdiff_t uniform_hits(Reduce r, int k, bool narrow, const Side<uint32_t>* sides, ptrdiff_t c0, ptrdiff_t c1,
                       const uint8_t* line, const int32_t* smax, const Linear& lin, int* cand, size_t& n_hits) {
#if defined(__SSE2__)
  auto run_k = [&](auto tag) -> ptrdiff_t {
    constexpr Reduce R = decltype(tag)::value;
    if (narrow) {
      switch (k) {
        case 1: return uniform_hits16<R, 1>(sides, c0, c1, line, smax, lin, cand, n_hits);
        case 2: return uniform_hits16<R, 2>(sides, c0, c1, line, smax, lin, cand, n_hits);
        case 3: return uniform_hits16<R, 3>(sides, c0, c1, line, smax, lin, cand, n_hits);
        default: return uniform_hits16<R, 4>(sides, c0, c1, line, smax, lin, cand, n_hits);
      }
    }
    switch (k) {
      case 1: return uniform_hits4<R, 1>(sides, c0, c1, line, smax, lin, cand, n_hits);
      case 2: return uniform_hits4<R, 2>(sides, c0, c1, line, smax, lin, cand, n_hits);
      case 3: return uniform_hits4<R, 3>(sides, c0, c1, line, smax, lin, cand, n_hits);
      default: return uniform_hits4<R, 4>(sides, c0, c1, line, smax, lin, cand, n_hits);
    }
  };
  switch (r) {
    case Reduce::kMin: return run_k(std::integral_constant<Reduce, Reduce::kMin>{});
    case Reduce::kMax: return run_k(std::integral_constant<Reduce, Reduce::kMax>{});
    case Reduce::kSum: return run_k(std::integral_constant<Reduce, Reduce::kSum>{});
  }
#endif
  (void)r;
  (void)k;
  (void)narrow;
  (void)sides;
  (void)c1;
  (void)line;
  (void)smax;
  (void)lin;
  (void)cand;
  (void)n_hits;
  return c0;
}

}  // namespace orthosonar::perception::detail
