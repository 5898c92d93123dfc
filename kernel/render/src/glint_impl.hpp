// The sun's glint on the sea (houle/render/sky.hpp's sun_glint), written once for every width: sky.cpp
// holds the scalar instance, the sea's light its batches (sea_light_impl.hpp). Only +, -, *,
// simd::div, simd::sqrt, simd::exp, comparisons and selects: every SIMD path gives the scalar bits.
#pragma once
#include <numbers>

#include "houle/render/sky.hpp"
#include "houle/simd/exp.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "optics_impl.hpp"

namespace houle::detail {

template <class V>
inline V gaussian_slope_density(V cos_theta_h, V s) {
  const V c2 = cos_theta_h * cos_theta_h;
  const V tan2 = simd::div(V(1.0f) - c2, c2);
  const V d = simd::div(simd::exp(V(0.0f) - simd::div(tan2, V(2.0f) * s)), V(2.0f * std::numbers::pi_v<float>) * s * c2 * c2);
  return simd::select(cos_theta_h > 0.0f, d, V(0.0f));
}

/// Smith's Lambda for Gaussian (Beckmann) slopes of variance s per axis, seen at cosine c from the mean
/// normal. Exact: Lambda = (e^{-a^2} / (a sqrt(pi)) - erfc(a)) / 2 with a = cot(theta) / sqrt(2 s);
/// here Walter et al. 2007's rational fit of it (eq. 27; G1 within ~0.4 %), which needs no exp or erfc.
template <class V>
inline V smith_lambda(V c, V s) {
  const V a = simd::div(c, simd::sqrt(max_as_std((V(1.0f) - c * c) * (V(2.0f) * s), V(1e-30f))));
  const V l = simd::div((V(1.0f) - V(1.259f) * a) + V(0.396f) * a * a, V(3.535f) * a + V(2.181f) * a * a);
  return simd::select(a >= 1.6f, V(0.0f), l);
}

/// sun_glint (sky.hpp) with the vectors as lanes.
template <class A>
inline simd::vfloat<A> sun_glint(const simd::vfloat<A> (&n)[3], const simd::vfloat<A> (&v)[3], const float (&l)[3],
                                 simd::vfloat<A> slope_variance, float n_outside, float n_inside) {
  using V = simd::vfloat<A>;
  const V zero(0.0f);
  const V cos_v = (n[0] * v[0] + n[1] * v[1]) + n[2] * v[2];
  const V cos_l = (n[0] * l[0] + n[1] * l[1]) + n[2] * l[2];
  V h[3] = {v[0] + l[0], v[1] + l[1], v[2] + l[2]};
  const V h_len = simd::sqrt((h[0] * h[0] + h[1] * h[1]) + h[2] * h[2]);
  const auto seen = (cos_v > 0.0f) & (cos_l > 0.0f) & (h_len > 0.0f);
  for (V& c : h) c = simd::div(c, h_len);
  const V cos_h = (n[0] * h[0] + n[1] * h[1]) + n[2] * h[2];
  const V v_dot_h = (v[0] * h[0] + v[1] * h[1]) + v[2] * h[2];
  const V s = max_as_std(slope_variance, zero) + V(sun_disc_slope_variance);
  const V d = gaussian_slope_density(cos_h, s);
  const V shadowing = simd::div(V(1.0f), (V(1.0f) + smith_lambda(cos_v, s)) + smith_lambda(cos_l, s));
  const V f = fresnel_terms<A>(v_dot_h, V(n_outside / n_inside)).reflectance;
  return simd::select(seen, simd::div(f * d * shadowing, V(4.0f) * cos_v), zero);
}

}  // namespace houle::detail
