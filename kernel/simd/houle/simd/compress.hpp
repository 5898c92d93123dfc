// Compaction: the lanes of a batch where a mask holds, written one after another (the order of the
// lanes kept). A kernel packs rays this way that only some pixels of a row send (docs/design.md 10).
// AVX-512 compresses in a register (its compress to memory is microcoded on Zen 4), AVX2 and SSE4.2
// permute by a table of the mask's bits, the others go lane by lane. Moving lanes changes no bits.
#pragma once
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"

namespace houle::simd {

/// p[0 .. count) = the lanes of v where m holds, in lane order; returns count. Up to width<A> values
/// are written at p (those past count meaningless): p must have room for them.
inline std::size_t compress_store(float* p, float v, bool m) {
  *p = v;
  return m ? 1 : 0;
}
inline std::size_t compress_store(std::uint32_t* p, std::int32_t v, bool m) {
  *p = static_cast<std::uint32_t>(v);
  return m ? 1 : 0;
}

#if HOULE_SIMD_BATCHES
namespace detail {

/// For each mask of n lanes (bit l: lane l kept), the kept lanes' numbers first, in order.
template <std::size_t N>
constexpr std::array<std::array<std::uint8_t, N>, (std::size_t(1) << N)> compress_lanes() {
  std::array<std::array<std::uint8_t, N>, (std::size_t(1) << N)> t{};
  for (std::size_t m = 0; m < t.size(); ++m) {
    std::size_t k = 0;
    for (std::size_t l = 0; l < N; ++l) {
      if (m >> l & 1) t[m][k++] = std::uint8_t(l);
    }
  }
  return t;
}

#if defined(__AVX2__)
/// AVX2: vpermps's lane numbers per 8-bit mask.
inline constexpr auto compress_lanes8 = [] {
  std::array<std::array<std::int32_t, 8>, 256> t{};
  const auto lanes = compress_lanes<8>();
  for (std::size_t m = 0; m < 256; ++m) {
    for (std::size_t l = 0; l < 8; ++l) t[m][l] = lanes[m][l];
  }
  return t;
}();
#endif

#if defined(__SSE4_2__)
/// SSE4.2: pshufb's byte numbers per 4-bit mask.
inline constexpr auto compress_bytes4 = [] {
  std::array<std::array<std::uint8_t, 16>, 16> t{};
  const auto lanes = compress_lanes<4>();
  for (std::size_t m = 0; m < 16; ++m) {
    for (std::size_t l = 0; l < 4; ++l) {
      for (std::size_t b = 0; b < 4; ++b) t[m][4 * l + b] = std::uint8_t(4 * lanes[m][l] + b);
    }
  }
  return t;
}();
#endif

/// The 32-bit lanes of v (bit patterns) where m holds, to p; returns their count.
template <class A>
inline std::size_t compress_bits(void* p, xsimd::batch<float, A> v, xsimd::batch_bool<float, A> m) {
#if defined(__AVX512F__)
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    const __mmask16 k = m;
    _mm512_storeu_ps(p, _mm512_maskz_compress_ps(k, v));
    return std::size_t(std::popcount(unsigned(k)));
  } else
#endif
#if defined(__AVX2__)
      if constexpr (std::is_base_of_v<xsimd::avx2, A>) {
    const unsigned bits = unsigned(_mm256_movemask_ps(m));
    const __m256i lanes = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(compress_lanes8[bits].data()));
    _mm256_storeu_ps(static_cast<float*>(p), _mm256_permutevar8x32_ps(v, lanes));
    return std::size_t(std::popcount(bits));
  } else
#endif
#if defined(__SSE4_2__)
      if constexpr (std::is_base_of_v<xsimd::sse4_2, A>) {
    const unsigned bits = unsigned(_mm_movemask_ps(m));
    const __m128i bytes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(compress_bytes4[bits].data()));
    _mm_storeu_si128(static_cast<__m128i*>(p), _mm_shuffle_epi8(_mm_castps_si128(v), bytes));
    return std::size_t(std::popcount(bits));
  } else
#endif
  {
    constexpr std::size_t W = xsimd::batch<float, A>::size;
    alignas(64) float values[W];
    alignas(64) bool keep[W];
    v.store_aligned(values);
    m.store_aligned(keep);
    std::size_t k = 0;
    for (std::size_t l = 0; l < W; ++l) {
      if (keep[l]) std::memcpy(static_cast<char*>(p) + 4 * k++, &values[l], 4);
    }
    return k;
  }
}

}  // namespace detail

template <class A>
inline std::size_t compress_store(float* p, xsimd::batch<float, A> v, xsimd::batch_bool<float, A> m) {
  return detail::compress_bits<A>(p, v, m);
}
template <class A>
inline std::size_t compress_store(std::uint32_t* p, xsimd::batch<std::int32_t, A> v, xsimd::batch_bool<float, A> m) {
  return detail::compress_bits<A>(p, bitcast_to_float(v), m);
}
#endif

}  // namespace houle::simd
