// 2^n and e^x for the SIMD layer, one template for the scalar path and every batch. Internal to houle:
// public headers never include this file.
#pragma once

#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"

namespace houle::simd {

/// 2^n for integral n in [-126, 127] (floats), built from the exponent bits: exact.
template <class V>
inline V pow2_exact(V n) {
  using I = decltype(to_int_exact(n));
  // A multiply, not a shift: gcc 12 warns inside the AVX-512 shift intrinsic (_mm512_undefined_epi32).
  return bitcast_to_float((to_int_exact(n) + I(127)) * I(1 << 23));
}

/// e^x for x in [-87, 88] (clamped there; NaN gives e^-87), relative error below 2e-7: Cephes' expf,
/// x = n ln 2 + r with ln 2 in two parts (exact n ln2_hi for |n| <= 127), a degree-7 polynomial in r,
/// then 2^n from the exponent bits. Only +, -, * and exact conversions: the same bits on every ISA,
/// unlike std::exp (tests/kernel/test_simd).
template <class V>
inline V exp(V x) {
  x = select(x > -87.0f, x, V(-87.0f));
  x = select(x < 88.0f, x, V(88.0f));
  const V n = round_nearest(x * 1.44269504088896341f);
  const V r = (x - n * 0.693359375f) - n * -2.12194440e-4f;
  const V r2 = r * r;
  const V p = (((((1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r + 4.1665795894e-2f) * r +
                1.6666665459e-1f) * r + 5.0000001201e-1f) * r2 + r + 1.0f;
  return p * pow2_exact(n);
}

}  // namespace houle::simd
