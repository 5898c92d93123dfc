// Batched float dispersion solver, written once for every width (included by sim_isa.cpp).
#pragma once
#include <cstddef>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

/// tanh x for 0 <= x, from + - * / only (so every ISA rounds alike). tanh(x/16) by Cephes' tanhf
/// polynomial (|x/16| <= 0.594 < 0.625, its domain), then four exact-in-form doublings
/// tanh 2u = 2 tanh u / (1 + tanh^2 u), each of relative condition number <= 1: errors add, a few
/// ulps in all. Above 9.5, tanh is 1 in float anyway.
template <class A>
inline simd::vfloat<A> tanh_nonnegative(simd::vfloat<A> x) {
  using V = simd::vfloat<A>;
  const V u = simd::min(x, V(9.5f)) * 0.0625f;
  const V z = u * u;
  V t = ((((-5.70498872745e-3f * z + 2.06390887954e-2f) * z - 5.37397155531e-2f) * z + 1.33314422036e-1f) * z -
         3.33332819422e-1f) * z * u + u;
  for (int i = 0; i < 4; ++i) t = simd::div(t + t, 1.0f + t * t);
  return t;
}

/// kh / k0h at y = k0h, for y > 0. Start: Hunt (1979) x^2 = y^2 + y / (1 + sum d_n y^n), 0.19 %
/// (needs no pow or cbrt, unlike Fenton & McKee); then Newton on x tanh x = y. The ratio x / y, not x,
/// is returned so that k = k0 x / y stays finite at both ends (y is clamped to [1e-30, 1e6]; above
/// 1e6, x = y exactly in float).
template <class A>
inline simd::vfloat<A> kh_over_k0h(simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  y = simd::max(simd::min(y, V(1e6f)), V(1e-30f));
  const V poly = 1.0f + y * (0.6666666667f + y * (0.3555555556f + y * (0.1608465608f +
                 y * (0.0632098765f + y * (0.0217540484f + y * 0.0065407983f)))));
  V x = simd::sqrt(y * y + simd::div(y, poly));
  for (int i = 0; i < 3; ++i) {
    const V t = tanh_nonnegative<A>(x);
    x = x - simd::div(x * t - y, t + x * (1.0f - t * t));
  }
  return simd::div(x, y);
}

template <class A>
inline simd::vfloat<A> dispersion_k_point(simd::vfloat<A> depth, float k0) {
  using V = simd::vfloat<A>;
  const auto wet = depth > V(0.0f);  // false for NaN too
  const V k = k0 * kh_over_k0h<A>(simd::select(wet, depth, V(1.0f)) * k0);
  return simd::select(wet, k, V(0.0f));
}

template <class A>
void dispersion_k_batch(float k0, const float* depth, std::size_t n, float* k) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    b.store(k, dispersion_k_point<A>(b.load(depth), k0));
  });
}

}  // namespace houle::detail
