// Gridded wave trains (houle/surface/train_grid.hpp), written once for every width (included by
// surface_isa.cpp; train_grid.cpp uses the scalar instantiation for train_grid_fields).
#pragma once
#include <algorithm>
#include <cstddef>

#include "houle/surface/train_grid.hpp"
#include "houle/simd/gather.hpp"
#include "height_field_impl.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
struct TrainGridLanes {
  simd::vfloat<A> phi, amplitude, kx, ky, fold, lean;
  simd::vmask<A> inside;  ///< on the grid (phi is then the grid's; else the far field's, without far_offset)
};

/// One train's fields at the points. Outside the grid phi is far_kx x + far_ky y (the caller
/// subtracts the far field's constant, which differs between the probe and the frame).
template <class A>
inline TrainGridLanes<A> train_grid_lanes(const TrainGrid& g, simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  TrainGridLanes<A> r{x * g.far_kx + y * g.far_ky, V(g.far_amplitude), V(g.far_kx), V(g.far_ky),
                      V(g.far_fold), V(g.far_lean), V(0.0f) != V(0.0f)};
  if (g.nx < 2) return r;
  const float inv_cell = 1.0f / g.cell, last_x = float(g.nx - 1), last_y = float(g.ny - 1);
  const V gx = (x - g.origin_x) * inv_cell, gy = (y - g.origin_y) * inv_cell;
  r.inside = (gx >= 0.0f) & (gy >= 0.0f) & (gx <= last_x) & (gy <= last_y);
  if (!simd::any(r.inside)) return r;
  // Lanes off the grid read its corner cell (any valid cell would do): their values are not selected.
  const V cx = simd::select(r.inside, gx, V(0.0f)), cy = simd::select(r.inside, gy, V(0.0f));
  const V i = simd::min(simd::floor_exact(cx), V(last_x - 1.0f)), j = simd::min(simd::floor_exact(cy), V(last_y - 1.0f));
  const V u = cx - i, v = cy - j;
  const simd::vint<A> n00 = simd::to_int_exact(j) * simd::vint<A>(std::int32_t(g.nx)) + simd::to_int_exact(i);
  const std::size_t row = g.nx;
  const auto lerp2 = [&](const float* q) {
    const V q00 = simd::gather(q, n00), q10 = simd::gather(q + 1, n00);
    const V q01 = simd::gather(q + row, n00), q11 = simd::gather(q + row + 1, n00);
    const V bottom = q00 + (q10 - q00) * u, top = q01 + (q11 - q01) * u;
    return bottom + (top - bottom) * v;
  };
  r.phi = simd::select(r.inside, lerp2(g.phi), r.phi);
  r.amplitude = simd::select(r.inside, lerp2(g.amplitude), r.amplitude);
  r.kx = simd::select(r.inside, lerp2(g.kx), r.kx);
  r.ky = simd::select(r.inside, lerp2(g.ky), r.ky);
  r.fold = simd::select(r.inside, lerp2(g.fold), r.fold);
  r.lean = simd::select(r.inside, lerp2(g.lean), r.lean);
  return r;
}

template <class A>
inline HeightFieldPoint<A> train_grid_point(const TrainGridFrame& f, simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  HeightFieldPoint<A> p{V(0.0f), V(0.0f), V(0.0f)};
  for (std::uint32_t t = 0; t < f.count; ++t) {
    const TrainGridLanes<A> l = train_grid_lanes<A>(f.trains[t], x, y);
    const V theta = l.phi - simd::select(l.inside, V(f.time_phase[t]), V(f.far_phase[t]));
    V s, c;
    simd::sincos(theta, s, c);
    V s1, c1;
    simd::sincos(theta - l.fold * c - l.lean * s, s1, c1);
    const V stretch = l.amplitude * c1 * (1.0f + l.fold * s - l.lean * c);
    p.height = p.height + l.amplitude * s1;
    p.grad_x = p.grad_x + stretch * l.kx;
    p.grad_y = p.grad_y + stretch * l.ky;
  }
  return p;
}

template <class A>
void train_grid_eval(const TrainGridFrame& f, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  eval_height_field<A>(x, y, n, out, [&](simd::vfloat<A> px, simd::vfloat<A> py) { return train_grid_point<A>(f, px, py); });
}

}  // namespace houle::detail
