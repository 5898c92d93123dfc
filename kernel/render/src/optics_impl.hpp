// Fresnel reflectance and reflected/refracted rays, written once for every width so that the marcher's
// shading can call them per packet (included by render_isa.cpp and optics.cpp).
// Only +, -, *, simd::div, simd::sqrt, min, max and select: correctly rounded everywhere but ARMv7
// NEON, so every SIMD path gives the scalar path's bits (tests/kernel/test_optics.cpp).
#pragma once
#include <cstddef>

#include "houle/render/optics.hpp"
#include "houle/simd/batch_loop.hpp"
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

// Batch loops over any n (simd::for_batches). Padding lanes of the tail get a harmless input.

template <class A>
void fresnel_batch(const float* cos_i, float eta, float* reflectance, std::size_t n) noexcept {
  const simd::vfloat<A> e = simd::splat<A>(eta);
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    b.store(reflectance, fresnel_terms<A>(b.load(cos_i), e).reflectance);
  });
}

template <class A>
void reflect_refract_batch(const ReflectRefractInput& in, std::size_t n, float n_outside, float n_inside,
                           ReflectRefractOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    // Padding lanes: straight down onto an upward normal.
    const InterfaceRays<A> r = interface_rays<A>(b.load(in.ix), b.load(in.iy), b.load(in.iz, -1.0f), b.load(in.nx),
                                                 b.load(in.ny), b.load(in.nz, 1.0f), n_outside, n_inside);
    b.store(out.rx, r.rx);
    b.store(out.ry, r.ry);
    b.store(out.rz, r.rz);
    b.store(out.tx, r.tx);
    b.store(out.ty, r.ty);
    b.store(out.tz, r.tz);
    b.store(out.reflectance, r.reflectance);
  });
}

}  // namespace houle::detail
