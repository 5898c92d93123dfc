// Fresnel reflectance and reflected/refracted rays, written once for every width so that the marcher's
// shading can call them per packet (included by render_isa.cpp and optics.cpp).
// Only +, -, *, simd::div, simd::sqrt, min, max and select: correctly rounded everywhere but ARMv7
// NEON, so every SIMD path gives the scalar path's bits (tests/kernel/test_optics.cpp).
#pragma once
#include <algorithm>
#include <cstddef>

#include "houle/render/optics.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
struct FresnelTerms {
  simd::vfloat<A> reflectance;  ///< K_r, 1 under total internal reflection
  simd::vfloat<A> cos_t;        ///< cosine of the refraction angle, 0 under TIR
  simd::vmask<A> tir;
};

/// Eq. 11 with cos_i clamped to [0, 1] and eta = n1 / n2 (incident over transmitted index).
/// r_s = (n1 c_i - n2 c_t) / (n1 c_i + n2 c_t), r_p = (n2 c_i - n1 c_t) / (n2 c_i + n1 c_t), both
/// divided through by n2. Under TIR the square root's argument is clamped to 0 rather than negative,
/// and the one 0/0 case (grazing incidence from the dense side) is kept out of the division.
template <class A>
inline FresnelTerms<A> fresnel_terms(simd::vfloat<A> cos_i, simd::vfloat<A> eta) {
  using V = simd::vfloat<A>;
  const V c = simd::min(simd::max(cos_i, V(0.0f)), V(1.0f));
  const V sin2_t = eta * eta * (V(1.0f) - c * c);
  const auto tir = sin2_t >= V(1.0f);
  const V cos_t = simd::sqrt(simd::max(V(1.0f) - sin2_t, V(0.0f)));
  const V ec = eta * c, et = eta * cos_t;
  const V rs = simd::div(ec - cos_t, simd::select(tir, V(1.0f), ec + cos_t));
  const V rp = simd::div(c - et, simd::select(tir, V(1.0f), c + et));
  const V r = V(0.5f) * (rs * rs + rp * rp);
  return {simd::select(tir, V(1.0f), r), cos_t, tir};
}

template <class A>
struct InterfaceRays {
  simd::vfloat<A> rx, ry, rz;  ///< reflected, unit
  simd::vfloat<A> tx, ty, tz;  ///< refracted, unit; 0 under TIR
  simd::vfloat<A> reflectance, cos_i, cos_t;
  simd::vmask<A> tir;
  simd::vmask<A> from_outside;  ///< arrived from the side the normal points to
};

/// docs/rendering.md 3.3. (ix, iy, iz): unit direction towards the surface; (nx, ny, nz): unit normal into
/// the n_outside medium. c = -N.I < 0 means the ray comes from the inside: the normal is flipped and the
/// indices swapped. Reflected R = I + 2cN, refracted T = eta I + (eta c - cos_t) N; both are unit for
/// unit inputs and are renormalised anyway so that float rounding does not accumulate along bounces.
template <class A>
inline InterfaceRays<A> interface_rays(simd::vfloat<A> ix, simd::vfloat<A> iy, simd::vfloat<A> iz,
                                       simd::vfloat<A> nx, simd::vfloat<A> ny, simd::vfloat<A> nz,
                                       float n_outside, float n_inside) {
  using V = simd::vfloat<A>;
  const V c_signed = V(0.0f) - (nx * ix + ny * iy + nz * iz);
  const auto outside = c_signed >= V(0.0f);
  const V side = simd::select(outside, V(1.0f), V(-1.0f));
  nx = nx * side;
  ny = ny * side;
  nz = nz * side;
  const V c = simd::min(c_signed * side, V(1.0f));
  const V eta = simd::select(outside, V(n_outside / n_inside), V(n_inside / n_outside));
  const FresnelTerms<A> f = fresnel_terms<A>(c, eta);

  InterfaceRays<A> out;
  const V two_c = c + c;
  V rx = ix + two_c * nx, ry = iy + two_c * ny, rz = iz + two_c * nz;
  const V inv_r = simd::div(V(1.0f), simd::sqrt(rx * rx + ry * ry + rz * rz));
  out.rx = rx * inv_r;
  out.ry = ry * inv_r;
  out.rz = rz * inv_r;

  const V k = eta * c - f.cos_t;
  const V tx = eta * ix + k * nx, ty = eta * iy + k * ny, tz = eta * iz + k * nz;
  // Under TIR T is not a ray; its length could be anything, so normalise a harmless stand-in.
  const V t_len2 = simd::select(f.tir, V(1.0f), tx * tx + ty * ty + tz * tz);
  const V inv_t = simd::select(f.tir, V(0.0f), simd::div(V(1.0f), simd::sqrt(t_len2)));
  out.tx = tx * inv_t;
  out.ty = ty * inv_t;
  out.tz = tz * inv_t;
  out.reflectance = f.reflectance;
  out.cos_i = c;
  out.cos_t = f.cos_t;
  out.tir = f.tir;
  out.from_outside = outside;
  return out;
}

// Batch loops over any n: full packets, then the tail through the same full-width code on a padded
// copy (so every lane is computed alike). Padding lanes get a harmless input.

template <class A>
void fresnel_batch(const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
  constexpr std::size_t W = simd::width<A>;
  const simd::vfloat<A> e = simd::splat<A>(eta);
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    simd::store<A>(reflectance + i, fresnel_terms<A>(simd::load<A>(cos_i + i), e).reflectance);
  }
  if (i < n) {
    alignas(64) float c[W] = {}, r[W];
    std::copy(cos_i + i, cos_i + n, c);
    simd::store<A>(r, fresnel_terms<A>(simd::load<A>(c), e).reflectance);
    std::copy(r, r + (n - i), reflectance + i);
  }
}

template <class A>
inline void interface_rays_store(const InterfaceRays<A>& r, float* const* out, std::size_t i) {
  simd::store<A>(out[0] + i, r.rx);
  simd::store<A>(out[1] + i, r.ry);
  simd::store<A>(out[2] + i, r.rz);
  simd::store<A>(out[3] + i, r.tx);
  simd::store<A>(out[4] + i, r.ty);
  simd::store<A>(out[5] + i, r.tz);
  simd::store<A>(out[6] + i, r.reflectance);
}

template <class A>
void reflect_refract_batch(const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                           ReflectRefractOutput out) noexcept {
  constexpr std::size_t W = simd::width<A>;
  const float* src[6] = {in.ix, in.iy, in.iz, in.nx, in.ny, in.nz};
  float* const dst[7] = {out.rx, out.ry, out.rz, out.tx, out.ty, out.tz, out.reflectance};
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    interface_rays_store<A>(interface_rays<A>(simd::load<A>(src[0] + i), simd::load<A>(src[1] + i),
                                              simd::load<A>(src[2] + i), simd::load<A>(src[3] + i),
                                              simd::load<A>(src[4] + i), simd::load<A>(src[5] + i),
                                              n_outside, n_inside),
                            dst, i);
  }
  if (i < n) {
    // Padding lanes: straight down onto an upward normal.
    alignas(64) float t[6][W] = {};
    alignas(64) float r[7][W];
    for (std::size_t j = 0; j < W; ++j) t[2][j] = -1.0f, t[5][j] = 1.0f;
    for (int k = 0; k < 6; ++k) std::copy(src[k] + i, src[k] + n, t[k]);
    float* const tmp[7] = {r[0], r[1], r[2], r[3], r[4], r[5], r[6]};
    interface_rays_store<A>(interface_rays<A>(simd::load<A>(t[0]), simd::load<A>(t[1]), simd::load<A>(t[2]),
                                              simd::load<A>(t[3]), simd::load<A>(t[4]), simd::load<A>(t[5]),
                                              n_outside, n_inside),
                            tmp, 0);
    for (int k = 0; k < 7; ++k) std::copy(r[k], r[k] + (n - i), dst[k] + i);
  }
}

}  // namespace houle::detail
