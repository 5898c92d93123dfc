// Gerstner height-field evaluation, written once for every width (included by surface_isa.cpp).
#pragma once
#include <algorithm>

#include "houle/surface/gerstner.hpp"
#include "height_field_impl.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
inline HeightFieldPoint<A> gerstner_point(const GerstnerFrame& f, simd::vfloat<A> x, simd::vfloat<A> y, int newton_steps) {
  using V = simd::vfloat<A>;
  V ux = x, uy = y;
  // Each pass evaluates the trains at u; the last pass only gives height and gradient.
  for (int step = 0;; ++step) {
    V px = ux, py = uy, z(0.0f), zx(0.0f), zy(0.0f);
    V mxx(0.0f), mxy(0.0f), myy(0.0f);  // M = sum q k A sin(theta) D D^T, Jacobian J = I - M
    for (std::uint32_t i = 0; i < f.count; ++i) {
      const V theta = simd::splat<A>(f.kx[i]) * ux + simd::splat<A>(f.ky[i]) * uy - simd::splat<A>(f.phase[i]);
      V s, c;
      simd::sincos(theta, s, c);
      px = px + simd::splat<A>(f.qax[i]) * c;
      py = py + simd::splat<A>(f.qay[i]) * c;
      z = z + simd::splat<A>(f.amp[i]) * s;
      const V ac = simd::splat<A>(f.amp[i]) * c;
      zx = zx + ac * simd::splat<A>(f.kx[i]);
      zy = zy + ac * simd::splat<A>(f.ky[i]);
      const V sx = s * simd::splat<A>(f.qax[i]);
      const V sy = s * simd::splat<A>(f.qay[i]);
      mxx = mxx + sx * simd::splat<A>(f.kx[i]);
      mxy = mxy + sx * simd::splat<A>(f.ky[i]);
      myy = myy + sy * simd::splat<A>(f.ky[i]);
    }
    const V jxx = 1.0f - mxx, jyy = 1.0f - myy, jxy = V(0.0f) - mxy;
    // sum(q k A) < 1 keeps J's eigenvalues in (0, 2): det > 0.
    const V inv_det = simd::div(V(1.0f), jxx * jyy - jxy * jxy);
    if (step == newton_steps) {
      // h(x) = z(u(x)): grad h = J^-T grad_u z, and J is symmetric.
      return {z, (jyy * zx - jxy * zy) * inv_det, (jxx * zy - jxy * zx) * inv_det};
    }
    const V rx = px - x, ry = py - y;
    ux = ux - (jyy * rx - jxy * ry) * inv_det;
    uy = uy - (jxx * ry - jxy * rx) * inv_det;
  }
}

template <class A>
void gerstner_eval(const GerstnerFrame& f, const float* x, const float* y, std::size_t n, GerstnerOutput out,
                   int newton_steps) noexcept {
  newton_steps = std::max(newton_steps, 1);
  eval_height_field<A>(x, y, n, out, [&](simd::vfloat<A> px, simd::vfloat<A> py) {
    return gerstner_point<A>(f, px, py, newton_steps);
  });
}

}  // namespace houle::detail
