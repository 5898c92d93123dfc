// Integer lanes (conversions, bit casts) and table lookups for the SIMD layer (apart from simd.hpp so that it can grow
// without touching the core vocabulary). vint<A> is int32 per lane; A = scalar gives plain int32.
// As in simd.hpp, each operation is a plain overload for scalar and a template on the batch's arch,
// so kernels call them without naming A. Internal to houle: public headers never include this file.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "houle/simd/simd.hpp"

#if HOULE_SIMD_BATCHES && (defined(__AVX2__) || defined(__AVX512F__))
#include <immintrin.h>
#endif

namespace houle::simd {

template <class A>
struct int_types;
template <>
struct int_types<scalar> {
  using i = std::int32_t;
};
#if HOULE_SIMD_BATCHES
template <class A>
struct int_types {
  using i = xsimd::batch<std::int32_t, A>;
};
#endif
template <class A>
using vint = typename int_types<A>::i;

/// Floats holding integers (|x| < 2^31) to int32: exact, the same on every ISA.
inline std::int32_t to_int_exact(float x) { return static_cast<std::int32_t>(x); }
/// int32 with |i| < 2^24 to float: exact.
inline float to_float_exact(std::int32_t i) { return static_cast<float>(i); }
/// The bits of each lane, reinterpreted (IEEE 754 single <-> int32).
inline std::int32_t bitcast_to_int(float x) { return std::bit_cast<std::int32_t>(x); }
inline float bitcast_to_float(std::int32_t i) { return std::bit_cast<float>(i); }

/// Byte B (0 = least significant) of each lane's word, sign-extended, by two shifts (unsigned in
/// the scalar path so that no signed overflow is involved).
template <int B>
inline std::int32_t signed_byte(std::int32_t w) {
  static_assert(B >= 0 && B < 4);
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(w) << (24 - 8 * B)) >> 24;
}

/// table[index] per lane.
inline std::int32_t gather(const std::int32_t* table, std::int32_t index) { return table[index]; }
inline float gather(const float* table, std::int32_t index) { return table[index]; }

/// The most floats gather_window reads on any ISA: a table padded to it serves every ISA's window.
inline constexpr std::int32_t max_window_floats = 32;

/// How many consecutive floats gather_window serves: 32 on AVX-512 and 16 on AVX2 (two vector loads
/// and a permute, much cheaper than a gather, docs/design.md 10), 0 elsewhere (kernels gather there).
template <class A>
constexpr std::int32_t window_floats() {
#if HOULE_SIMD_BATCHES && defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return 32;
#endif
#if HOULE_SIMD_BATCHES && defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A>) return 16;
#endif
  return 0;
}

/// The smallest and the largest lane.
inline void lane_range(std::int32_t v, std::int32_t& lo, std::int32_t& hi) { lo = hi = v; }
/// window[index] per lane (below: its batch form).
inline float gather_window(const float* window, std::int32_t index) { return window[index]; }
/// (pairs[2 index], pairs[2 index + 1]) per lane (below: its batch forms).
inline void gather_pair(const float* pairs, std::int32_t index, float& first, float& second) {
  first = pairs[2 * std::size_t(index)];
  second = pairs[2 * std::size_t(index) + 1];
}
/// (table[index], table[index + 1]) per lane (below: its batch form).
inline void gather_adjacent(const float* table, std::int32_t index, float& first, float& second) {
  first = table[index];
  second = table[std::size_t(index) + 1];
}
inline void gather_pair(const std::int32_t* pairs, std::int32_t index, std::int32_t& first, std::int32_t& second) {
  first = pairs[2 * std::size_t(index)];
  second = pairs[2 * std::size_t(index) + 1];
}

#if HOULE_SIMD_BATCHES
template <class A>
inline xsimd::batch<std::int32_t, A> to_int_exact(xsimd::batch<float, A> x) {
#if defined(__AVX512F__)
  // xsimd's conversion goes through _mm512_cvttps_epi32, whose _mm512_undefined_epi32 trips gcc 12's
  // -Wuninitialized once inlined; the zero-masked form is the same instruction without it.
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return _mm512_maskz_cvttps_epi32(static_cast<__mmask16>(0xFFFF), x);
#endif
  return xsimd::batch_cast<std::int32_t>(x);
}
template <class A>
inline xsimd::batch<float, A> to_float_exact(xsimd::batch<std::int32_t, A> i) {
  return xsimd::batch_cast<float>(i);
}
template <class A>
inline xsimd::batch<std::int32_t, A> bitcast_to_int(xsimd::batch<float, A> x) {
  return xsimd::bitwise_cast<xsimd::batch<std::int32_t, A>>(x);
}
template <class A>
inline xsimd::batch<float, A> bitcast_to_float(xsimd::batch<std::int32_t, A> i) {
  return xsimd::bitwise_cast<xsimd::batch<float, A>>(i);
}
template <int B, class A>
inline xsimd::batch<std::int32_t, A> signed_byte(xsimd::batch<std::int32_t, A> w) {
  static_assert(B >= 0 && B < 4);
  if constexpr (B == 3) {
    return w >> 24;  // arithmetic: signed lanes
  } else {
    return (w << (24 - 8 * B)) >> 24;
  }
}
/// AVX2 and AVX-512 use the gather instructions (xsimd 8.1's integer gather falls back to inserts,
/// docs/design.md 10); the others load lane by lane.
template <class A>
inline xsimd::batch<std::int32_t, A> gather(const std::int32_t* table, xsimd::batch<std::int32_t, A> index) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    return _mm512_i32gather_epi32(index, table, 4);
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
    return _mm256_i32gather_epi32(table, index, 4);
  } else
#endif
  {
    constexpr std::size_t W = xsimd::batch<std::int32_t, A>::size;
    alignas(64) std::int32_t idx[W], out[W];
    index.store_aligned(idx);
    for (std::size_t l = 0; l < W; ++l) out[l] = table[idx[l]];
    return xsimd::batch<std::int32_t, A>::load_aligned(out);
  }
}
template <class A>
inline xsimd::batch<float, A> gather(const float* table, xsimd::batch<std::int32_t, A> index) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    // The masked form: the plain one's _mm512_undefined_ps trips gcc 12's -Wuninitialized.
    return _mm512_mask_i32gather_ps(_mm512_setzero_ps(), static_cast<__mmask16>(0xFFFF), index, table, 4);
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
    return _mm256_i32gather_ps(table, index, 4);
  } else
#endif
  {
    constexpr std::size_t W = xsimd::batch<float, A>::size;
    alignas(64) std::int32_t idx[W];
    alignas(64) float out[W];
    index.store_aligned(idx);
    for (std::size_t l = 0; l < W; ++l) out[l] = table[idx[l]];
    return xsimd::batch<float, A>::load_aligned(out);
  }
}
template <class A>
inline void lane_range(xsimd::batch<std::int32_t, A> v, std::int32_t& lo, std::int32_t& hi) {
  constexpr std::size_t W = xsimd::batch<std::int32_t, A>::size;
  alignas(64) std::int32_t lanes[W];
  v.store_aligned(lanes);
  lo = hi = lanes[0];
  for (std::size_t l = 1; l < W; ++l) {
    lo = lanes[l] < lo ? lanes[l] : lo;
    hi = lanes[l] > hi ? lanes[l] : hi;
  }
}
/// window[index] per lane, every index in [0, window_floats<A>()) and that many floats readable at
/// `window`: the values gather(window, index) gives.
template <class A>
inline xsimd::batch<float, A> gather_window(const float* window, xsimd::batch<std::int32_t, A> index) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    return _mm512_permutex2var_ps(_mm512_loadu_ps(window), index, _mm512_loadu_ps(window + 16));
  } else
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
    const __m256 low = _mm256_permutevar8x32_ps(_mm256_loadu_ps(window), index);
    const __m256 high = _mm256_permutevar8x32_ps(_mm256_loadu_ps(window + 8), index);
    return _mm256_blendv_ps(low, high, _mm256_castsi256_ps(_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7))));
  } else
#endif
  {
    return gather(window, index);
  }
}
namespace detail {
/// (table[s index], table[s index + 1]) per lane, s = Scale / 4 (detail::gather_two), lane by lane.
template <int Scale, class T, class A>
inline void gather_two_lanes(const T* table, xsimd::batch<std::int32_t, A> index, xsimd::batch<T, A>& first,
                             xsimd::batch<T, A>& second) {
  static_assert(sizeof(T) == 4 && (Scale == 4 || Scale == 8));
  constexpr std::size_t W = xsimd::batch<T, A>::size;
  alignas(64) std::int32_t idx[W];
  alignas(64) T f[W], s[W];
  index.store_aligned(idx);
  for (std::size_t l = 0; l < W; ++l) {
    const std::size_t k = std::size_t(idx[l]) * (Scale / 4);
    f[l] = table[k];
    s[l] = table[k + 1];
  }
  first = xsimd::batch<T, A>::load_aligned(f);
  second = xsimd::batch<T, A>::load_aligned(s);
}
/// Two neighbouring floats at table + Scale bytes x index as one 64-bit element per lane, so that AVX2
/// and AVX-512 fetch them with half the gathered elements of two float gathers (a gather's cost is per
/// element, docs/design.md 10); the others load lane by lane.
template <int Scale, class A>
inline void gather_two(const float* table, xsimd::batch<std::int32_t, A> index, xsimd::batch<float, A>& first,
                       xsimd::batch<float, A>& second) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    // The masked forms: the plain ones' _mm512_undefined_pd trips gcc 12's -Wuninitialized.
    const __m512 a = _mm512_castpd_ps(_mm512_mask_i32gather_pd(_mm512_setzero_pd(), static_cast<__mmask8>(0xFF),
                                                               _mm512_castsi512_si256(index), table, Scale));
    const __m512 b = _mm512_castpd_ps(_mm512_mask_i32gather_pd(_mm512_setzero_pd(), static_cast<__mmask8>(0xFF),
                                                               _mm512_extracti64x4_epi64(index, 1), table, Scale));
    first = _mm512_permutex2var_ps(a, _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30), b);
    second = _mm512_permutex2var_ps(a, _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31), b);
    return;
  }
#endif
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
    // The masked form, as above (here _mm256_undefined_pd).
    const double* p = reinterpret_cast<const double*>(table);
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    const __m256 a = _mm256_castpd_ps(_mm256_mask_i32gather_pd(_mm256_setzero_pd(), p, _mm256_castsi256_si128(index), all, Scale));
    const __m256 b = _mm256_castpd_ps(_mm256_mask_i32gather_pd(_mm256_setzero_pd(), p, _mm256_extracti128_si256(index, 1), all, Scale));
    // Per 128-bit half, (a0 a2 b0 b2) and (a1 a3 b1 b3); then the halves' middle 64-bit elements swap.
    const __m256 even = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)), odd = _mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1));
    first = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(even), _MM_SHUFFLE(3, 1, 2, 0)));
    second = _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(odd), _MM_SHUFFLE(3, 1, 2, 0)));
    return;
  }
#endif
  gather_two_lanes<Scale>(table, index, first, second);
}
}  // namespace detail

/// (pairs[2 index], pairs[2 index + 1]) per lane, index < 2^28 (detail::gather_two).
template <class A>
inline void gather_pair(const float* pairs, xsimd::batch<std::int32_t, A> index, xsimd::batch<float, A>& first,
                        xsimd::batch<float, A>& second) {
  detail::gather_two<8>(pairs, index, first, second);
}
/// (table[index], table[index + 1]) per lane (detail::gather_two): a bilinear tap's two
/// corners along a row.
template <class A>
inline void gather_adjacent(const float* table, xsimd::batch<std::int32_t, A> index, xsimd::batch<float, A>& first,
                            xsimd::batch<float, A>& second) {
  detail::gather_two<4>(table, index, first, second);
}
/// The same for int32 pairs: on AVX2 and AVX-512 the float pairs' instructions, which only move bits.
template <class A>
inline void gather_pair(const std::int32_t* pairs, xsimd::batch<std::int32_t, A> index, xsimd::batch<std::int32_t, A>& first,
                        xsimd::batch<std::int32_t, A>& second) {
#if defined(__AVX2__)
  if constexpr (std::is_base_of_v<xsimd::avx2, A> || std::is_base_of_v<xsimd::avx512f, A>) {
    xsimd::batch<float, A> f, s;
    gather_pair(reinterpret_cast<const float*>(pairs), index, f, s);
    first = bitcast_to_int(f);
    second = bitcast_to_int(s);
    return;
  }
#endif
  detail::gather_two_lanes<8>(pairs, index, first, second);
}
#endif

}  // namespace houle::simd
