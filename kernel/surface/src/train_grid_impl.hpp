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
  simd::vfloat<A> phi, b_re, b_im, kx, ky, fold, lean;
  simd::vfloat<A> b_re_x, b_re_y, b_im_x, b_im_y;  ///< dB/dx, dB/dy within the cell (0 off the grid)
  simd::vmask<A> inside;  ///< on the grid (phi is then the grid's; else the far field's, without far_offset)
};

/// One train's fields at the points. Outside the grid phi is far_kx x + far_ky y (the caller
/// subtracts the far field's constant, which differs between the probe and the frame).
template <class A>
inline TrainGridLanes<A> train_grid_lanes(const TrainGrid& g, simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  const V zero(0.0f);
  TrainGridLanes<A> r{x * g.far_kx + y * g.far_ky, V(g.far_amplitude), zero, V(g.far_kx), V(g.far_ky),
                      V(g.far_fold), V(g.far_lean), zero, zero, zero, zero, zero != zero};
  if (g.nx < 2) return r;
  const float inv_cell = 1.0f / g.cell, last_x = float(g.nx - 1), last_y = float(g.ny - 1);
  const V gx = (x - g.origin_x) * inv_cell, gy = (y - g.origin_y) * inv_cell;
  r.inside = (gx >= 0.0f) & (gy >= 0.0f) & (gx <= last_x) & (gy <= last_y);
  if (!simd::any(r.inside)) return r;
  // Lanes off the grid read its corner cell (any valid cell would do): their values are not selected.
  const V cx = simd::select(r.inside, gx, zero), cy = simd::select(r.inside, gy, zero);
  const V i = simd::min(simd::floor_exact(cx), V(last_x - 1.0f)), j = simd::min(simd::floor_exact(cy), V(last_y - 1.0f));
  const V u = cx - i, v = cy - j;
  const simd::vint<A> n00 = simd::to_int_exact(j) * simd::vint<A>(std::int32_t(g.nx)) + simd::to_int_exact(i);
  const std::size_t row = g.nx;
  struct Corners {
    V q00, q10, q01, q11;
  };
  const auto corners = [&](const float* q) {
    return Corners{simd::gather(q, n00), simd::gather(q + 1, n00), simd::gather(q + row, n00), simd::gather(q + row + 1, n00)};
  };
  const auto lerp2 = [&](const Corners& c) {
    const V bottom = c.q00 + (c.q10 - c.q00) * u, top = c.q01 + (c.q11 - c.q01) * u;
    return bottom + (top - bottom) * v;
  };
  const auto field = [&](const float* q, V outside) { return simd::select(r.inside, lerp2(corners(q)), outside); };
  r.phi = field(g.phi, r.phi);
  r.kx = field(g.kx, r.kx);
  r.ky = field(g.ky, r.ky);
  r.fold = field(g.fold, r.fold);
  r.lean = field(g.lean, r.lean);
  // B and its derivatives in the cell (per metre).
  const auto with_gradient = [&](const float* q, V& value, V& d_dx, V& d_dy) {
    const Corners c = corners(q);
    value = simd::select(r.inside, lerp2(c), value);
    const V dx = ((c.q10 - c.q00) + ((c.q11 - c.q01) - (c.q10 - c.q00)) * v) * inv_cell;
    const V dy = ((c.q01 - c.q00) + ((c.q11 - c.q10) - (c.q01 - c.q00)) * u) * inv_cell;
    d_dx = simd::select(r.inside, dx, zero);
    d_dy = simd::select(r.inside, dy, zero);
  };
  with_gradient(g.b_re, r.b_re, r.b_re_x, r.b_re_y);
  with_gradient(g.b_im, r.b_im, r.b_im_x, r.b_im_y);
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
    // w = B e^{i theta}; its derivative along an axis: e^{i theta} dB + i k w.
    const V w_re = l.b_re * c - l.b_im * s, w_im = l.b_re * s + l.b_im * c;
    const V delta = l.fold * w_re + l.lean * w_im;
    V sd, cd;
    simd::sincos(delta, sd, cd);
    p.height = p.height + (w_im * cd - w_re * sd);
    const V slope = w_im * sd + w_re * cd;  // -d h / d delta
    const auto derivative = [&](V db_re, V db_im, V k) {
      const V dw_re = (db_re * c - db_im * s) - k * w_im, dw_im = (db_re * s + db_im * c) + k * w_re;
      return (dw_im * cd - dw_re * sd) - slope * (l.fold * dw_re + l.lean * dw_im);
    };
    p.grad_x = p.grad_x + derivative(l.b_re_x, l.b_im_x, l.kx);
    p.grad_y = p.grad_y + derivative(l.b_re_y, l.b_im_y, l.ky);
  }
  return p;
}

template <class A>
void train_grid_eval(const TrainGridFrame& f, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  eval_height_field<A>(x, y, n, out, [&](simd::vfloat<A> px, simd::vfloat<A> py) { return train_grid_point<A>(f, px, py); });
}

}  // namespace houle::detail
