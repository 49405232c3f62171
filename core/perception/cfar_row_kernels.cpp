// The row kernels of the integer CFAR path: side sums reduced or selected over a row,
// column and row prefix sums, cells above the gate; SSE2 for 8-bit images (32-bit sums),
// scalar otherwise and for the tail.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/perception/cfar_detail.hpp"

namespace orthosonar::perception::detail {

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

// The instances the integer path uses.
template void reduce_equal_sides<Reduce::kMin>(const Side<uint32_t>*, int, ptrdiff_t, ptrdiff_t, int32_t*);
template void reduce_equal_sides<Reduce::kMax>(const Side<uint32_t>*, int, ptrdiff_t, ptrdiff_t, int32_t*);
template void reduce_equal_sides<Reduce::kSum>(const Side<uint32_t>*, int, ptrdiff_t, ptrdiff_t, int32_t*);
template void reduce_equal_sides<Reduce::kMin>(const Side<uint64_t>*, int, ptrdiff_t, ptrdiff_t, int64_t*);
template void reduce_equal_sides<Reduce::kMax>(const Side<uint64_t>*, int, ptrdiff_t, ptrdiff_t, int64_t*);
template void reduce_equal_sides<Reduce::kSum>(const Side<uint64_t>*, int, ptrdiff_t, ptrdiff_t, int64_t*);
template void select_sides(CfarMethod, const Side<uint32_t>*, int, bool, ptrdiff_t, ptrdiff_t, int32_t*, int32_t*);
template void select_sides(CfarMethod, const Side<uint64_t>*, int, bool, ptrdiff_t, ptrdiff_t, int64_t*, int32_t*);
template void add_row(const uint32_t*, const uint8_t*, uint32_t*, size_t);
template void add_row(const uint64_t*, const uint8_t*, uint64_t*, size_t);
template void add_row(const uint64_t*, const uint16_t*, uint64_t*, size_t);
template void row_prefix(const uint8_t*, uint32_t*, size_t);
template void row_prefix(const uint8_t*, uint64_t*, size_t);
template void row_prefix(const uint16_t*, uint64_t*, size_t);
template size_t count_above(const uint8_t*, size_t, int64_t);
template size_t count_above(const uint16_t*, size_t, int64_t);
template size_t columns_above(const uint8_t*, size_t, int64_t, int*);
template size_t columns_above(const uint16_t*, size_t, int64_t, int*);

}  // namespace orthosonar::perception::detail
