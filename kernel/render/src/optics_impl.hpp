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

template <class A>
struct Direction {
  simd::vfloat<A> x, y, z;
};

/// (x, y, z) / |(x, y, z)|, divided once.
template <class A>
inline Direction<A> normalized(simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z) {
  using V = simd::vfloat<A>;
  const V inv = simd::div(V(1.0f), simd::sqrt(x * x + y * y + z * z));
  return {x * inv, y * inv, z * inv};
}

/// docs/rendering.md 3.3 (a): the eq. 8 normal of a height field of gradient (gx, gy), met by the unit
/// ray d from above (side > 0) or below (side < 0), bent where it faces away from the ray until
/// N.d = -0.01 (from below +0.01) and renormalised; (0, 0, 1) where side is 0 (no sea hit).
template <class A>
inline Direction<A> sea_normal(simd::vfloat<A> side, simd::vfloat<A> gx, simd::vfloat<A> gy, simd::vfloat<A> dx,
                               simd::vfloat<A> dy, simd::vfloat<A> dz) {
  using V = simd::vfloat<A>;
  const auto above = side > V(0.0f), below = side < V(0.0f);
  const Direction<A> n = normalized<A>(-gx, -gy, V(1.0f));
  const V want = simd::select(above, V(-0.01f), V(0.01f));
  const V nd = n.x * dx + n.y * dy + n.z * dz;
  const auto bend = (above & (nd > want)) | (below & (nd < want));
  const V k = nd - want;
  const Direction<A> b = normalized<A>(n.x - k * dx, n.y - k * dy, n.z - k * dz);
  const auto sea = above | below;
  return {simd::select(sea, simd::select(bend, b.x, n.x), V(0.0f)), simd::select(sea, simd::select(bend, b.y, n.y), V(0.0f)),
          simd::select(sea, simd::select(bend, b.z, n.z), V(1.0f))};
}

/// docs/rendering.md 3.3 (b): a unit direction that must leave the sea upwards, its z raised to at least
/// min_dz and renormalised ((0, 0, 1) for one straight down).
template <class A>
inline Direction<A> lifted(simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z, float min_dz) {
  using V = simd::vfloat<A>;
  const auto keep = z >= V(min_dz);
  const V h2 = x * x + y * y;
  const auto level = h2 > V(0.0f);
  const V k = simd::select(level, simd::sqrt(simd::div(V(1.0f - min_dz * min_dz), simd::select(level, h2, V(1.0f)))),
                           V(0.0f));
  return {simd::select(keep, x, x * k), simd::select(keep, y, y * k),
          simd::select(keep, z, simd::select(level, V(min_dz), V(1.0f)))};
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

template <class A>
void sea_normals_batch(const SeaNormalsInput& in, std::size_t n, SeaNormalsOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const Direction<A> v = sea_normal<A>(b.load(in.side), b.load(in.gx), b.load(in.gy), b.load(in.dx), b.load(in.dy),
                                         b.load(in.dz, -1.0f));
    b.store(out.nx, v.x);
    b.store(out.ny, v.y);
    b.store(out.nz, v.z);
  });
}

template <class A>
void air_directions_batch(const AirDirectionsInput& in, std::size_t n, float min_dz, AirDirectionsOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const V side = b.load(in.side);
    const auto above = side > V(0.0f), below = side < V(0.0f);
    // Padding lanes: straight up.
    const Direction<A> r = lifted<A>(b.load(in.rx), b.load(in.ry), b.load(in.rz, 1.0f), min_dz);
    const Direction<A> t = lifted<A>(b.load(in.tx), b.load(in.ty), b.load(in.tz, 1.0f), min_dz);
    b.store(out.x, simd::select(above, r.x, simd::select(below, t.x, b.load(in.dx))));
    b.store(out.y, simd::select(above, r.y, simd::select(below, t.y, b.load(in.dy))));
    b.store(out.z, simd::select(above, r.z, simd::select(below, t.z, b.load(in.dz, 1.0f))));
  });
}

}  // namespace houle::detail
