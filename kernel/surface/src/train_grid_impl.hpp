// Gridded wave trains (houle/surface/train_grid.hpp), written once for every width (included by
// surface_isa.cpp; train_grid.cpp uses the scalar instantiation for train_grid_fields).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "houle/surface/node_footprint.hpp"
#include "houle/surface/train_grid.hpp"
#include "houle/simd/gather.hpp"
#include "height_field_impl.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
struct TrainGridLanes {
  simd::vfloat<A> phi, b_re, b_im, kx, ky, fold, lean;
  simd::vfloat<A> b_re_x, b_re_y, b_im_x, b_im_y;  ///< dB/dx, dB/dy (0 along an axis clamped to the grid)
};

/// One train's fields at the points. Off the grid the nearest point of its edge goes on along its wave
/// vector: phi grows by k . (p - edge point), the other fields stay its own (docs/physics.md 2.8), so the
/// sea beyond the domain continues the sea at its edge. Without a grid the train is its far field,
/// phi = far_kx x + far_ky y (the caller subtracts the far field's constant, which differs between
/// the probe and the frame).
template <class A>
inline TrainGridLanes<A> train_grid_lanes(const TrainGrid& g, simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  const V zero(0.0f);
  TrainGridLanes<A> r{x * g.far_kx + y * g.far_ky, V(g.far_amplitude), zero, V(g.far_kx), V(g.far_ky),
                      V(g.far_fold), V(g.far_lean), zero, zero, zero, zero};
  if (g.nx < 2) return r;
  const float inv_cell = 1.0f / g.cell, last_x = float(g.nx - 1), last_y = float(g.ny - 1);
  const V gx = (x - g.origin_x) * inv_cell, gy = (y - g.origin_y) * inv_cell;
  // Clamped to the grid; NaN reads node 0 (its lanes are NaN by the phase below).
  const auto in_x = (gx >= 0.0f) & (gx <= last_x), in_y = (gy >= 0.0f) & (gy <= last_y);
  const V cx = simd::select(in_x, gx, simd::select(gx > last_x, V(last_x), zero));
  const V cy = simd::select(in_y, gy, simd::select(gy > last_y, V(last_y), zero));
  const V i = simd::min(simd::floor_exact(cx), V(last_x - 1.0f)), j = simd::min(simd::floor_exact(cy), V(last_y - 1.0f));
  const V u = cx - i, v = cy - j;
  const simd::vint<A> n00 = simd::to_int_exact(j) * simd::vint<A>(std::int32_t(g.nx)) + simd::to_int_exact(i);
  const std::size_t row = g.nx;
  struct Corners {
    V q00, q10, q01, q11;
  };
  // Along a row of the surface frame, a batch's cells often lie within a few nodes of each other:
  // then each corner comes from a window of the field (two loads and a permute), not a gather
  // (docs/design.md 10). The same values, so the same bits as the scalar path.
  std::int32_t window = -1;  // the first node of the window, or -1: gather
  if constexpr (simd::window_floats<A>() > 0) {
    std::int32_t lo, hi;
    simd::lane_range(n00, lo, hi);
    const std::int64_t nodes = std::int64_t(g.nx) * g.ny;
    if (hi - lo + 1 < simd::window_floats<A>() && std::int64_t(lo) + std::int64_t(row) + simd::window_floats<A>() <= nodes) {
      window = lo;
    }
  }
  const auto corners = [&](const float* q) {
    if constexpr (simd::window_floats<A>() > 0) {
      if (window >= 0) {
        const simd::vint<A> o = n00 - simd::vint<A>(window), o1 = o + simd::vint<A>(1);
        const float *w0 = q + window, *w1 = w0 + row;
        return Corners{simd::gather_window(w0, o), simd::gather_window(w0, o1), simd::gather_window(w1, o),
                       simd::gather_window(w1, o1)};
      }
    }
    return Corners{simd::gather(q, n00), simd::gather(q + 1, n00), simd::gather(q + row, n00), simd::gather(q + row + 1, n00)};
  };
  const auto lerp2 = [&](const Corners& c) {
    const V bottom = c.q00 + (c.q10 - c.q00) * u, top = c.q01 + (c.q11 - c.q01) * u;
    return bottom + (top - bottom) * v;
  };
  const auto field = [&](const float* q) { return lerp2(corners(q)); };
  r.kx = field(g.kx);
  r.ky = field(g.ky);
  r.fold = field(g.fold);
  r.lean = field(g.lean);
  // Off the grid along an axis, the offset from the edge point along it (exactly 0 on the grid).
  const V off_x = simd::select(in_x, zero, (gx - cx) * g.cell), off_y = simd::select(in_y, zero, (gy - cy) * g.cell);
  r.phi = field(g.phi) + (r.kx * off_x + r.ky * off_y);
  // B and its derivatives in the cell (per metre); B is constant off the grid along a clamped axis.
  const auto with_gradient = [&](const float* q, V& value, V& d_dx, V& d_dy) {
    const Corners c = corners(q);
    value = lerp2(c);
    const V dx = ((c.q10 - c.q00) + ((c.q11 - c.q01) - (c.q10 - c.q00)) * v) * inv_cell;
    const V dy = ((c.q01 - c.q00) + ((c.q11 - c.q10) - (c.q01 - c.q00)) * u) * inv_cell;
    d_dx = simd::select(in_x, dx, zero);
    d_dy = simd::select(in_y, dy, zero);
  };
  with_gradient(g.b_re, r.b_re, r.b_re_x, r.b_re_y);
  with_gradient(g.b_im, r.b_im, r.b_im_x, r.b_im_y);
  return r;
}

/// The per-point part of node_wave_weight (houle/surface/node_footprint.hpp): the squared pixel
/// footprint across the view and its stretch along it, per unit of (k . e)^2 (e the point's offset from
/// the eye's ground point), and the squared grid limit.
template <class A>
struct FootprintLanes {
  simd::vfloat<A> ex, ey, across2, stretch, grid2;
};

template <class A>
inline FootprintLanes<A> footprint_lanes(const NodeFootprint& f, simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  FootprintLanes<A> l;
  l.ex = x - f.eye_x;
  l.ey = y - f.eye_y;
  const V r2 = l.ex * l.ex + l.ey * l.ey, h2(f.eye_height * f.eye_height), t2 = r2 + h2;
  const V theta2(f.pixel_angle * f.pixel_angle);
  // The footprint is t theta across the view and t theta / |d_z| along it, with |d_z| = |eye height| / t
  // held at 1e-3 as the marcher holds it (docs/rendering.md 5.2). Along - across, squared, over r^2:
  // theta^2 t^2 / h^2, or with |d_z| held, theta^2 t^2 (1e6 - 1) / r^2 (r > 0 there).
  const auto steep = h2 >= t2 * 1e-6f;
  const V den = simd::select(steep, h2, r2);
  l.across2 = theta2 * t2;
  l.stretch = simd::div(l.across2 * simd::select(steep, V(1.0f), V(1e6f - 1.0f)), simd::select(den > 1e-30f, den, V(1e-30f)));
  l.grid2 = V(4.0f * f.cell * f.cell);
  return l;
}

/// node_wave_weight per lane: 1 while the phase across the footprint (along k) is at most pi and that
/// across two cells at most pi, a smoothstep to 0 at 2 pi.
template <class A>
inline simd::vfloat<A> footprint_weight(const FootprintLanes<A>& l, simd::vfloat<A> kx, simd::vfloat<A> ky) {
  using V = simd::vfloat<A>;
  const V k2 = kx * kx + ky * ky, ke = kx * l.ex + ky * l.ey;
  const V pixel = l.across2 * k2 + l.stretch * (ke * ke), grid = l.grid2 * k2;
  const V p = simd::sqrt(simd::select(pixel < grid, grid, pixel));
  V u = V(2.0f) - p * 0.318309886f;  // 1 / pi
  u = simd::select(u > 0.0f, u, V(0.0f));
  u = simd::select(u < 1.0f, u, V(1.0f));
  return u * u * (V(3.0f) - 2.0f * u);
}

/// The summed trains at the points; with a footprint (Filtered), each train weighted by
/// footprint_weight and the slope variance it loses, per axis, added to `variance`: a train of
/// amplitude |B| and wavenumber k has slope variance (k |B|)^2 / 2 along k, (k |B|)^2 / 4 per axis of
/// the isotropic roughness the glint takes (docs/rendering.md 5.5).
template <class A, bool Filtered>
inline HeightFieldPoint<A> train_grid_point(const TrainGridFrame& f, simd::vfloat<A> x, simd::vfloat<A> y,
                                            const FootprintLanes<A>* footprint, simd::vfloat<A>* variance) {
  using V = simd::vfloat<A>;
  HeightFieldPoint<A> p{V(0.0f), V(0.0f), V(0.0f)};
  for (std::uint32_t t = 0; t < f.count; ++t) {
    const TrainGridLanes<A> l = train_grid_lanes<A>(f.trains[t], x, y);
    V weight(1.0f);
    if constexpr (Filtered) {
      weight = footprint_weight<A>(*footprint, l.kx, l.ky);
      const V b2 = l.b_re * l.b_re + l.b_im * l.b_im, k2 = l.kx * l.kx + l.ky * l.ky;
      *variance = *variance + (V(1.0f) - weight * weight) * (b2 * k2 * 0.25f);
      if (!simd::any(weight > 0.0f)) continue;  // faded everywhere here: nothing to add
    }
    const V theta = l.phi - V(f.trains[t].nx < 2 ? f.far_phase[t] : f.time_phase[t]);
    V s, c;
    simd::sincos(theta, s, c);
    // w = B e^{i theta}; its derivative along an axis: e^{i theta} dB + i k w.
    const V w_re = l.b_re * c - l.b_im * s, w_im = l.b_re * s + l.b_im * c;
    const V delta = l.fold * w_re + l.lean * w_im;
    V sd, cd;
    simd::sincos(delta, sd, cd);
    const V slope = w_im * sd + w_re * cd;  // -d h / d delta
    const auto derivative = [&](V db_re, V db_im, V k) {
      const V dw_re = (db_re * c - db_im * s) - k * w_im, dw_im = (db_re * s + db_im * c) + k * w_re;
      return (dw_im * cd - dw_re * sd) - slope * (l.fold * dw_re + l.lean * dw_im);
    };
    const V h = w_im * cd - w_re * sd;
    const V gx = derivative(l.b_re_x, l.b_im_x, l.kx), gy = derivative(l.b_re_y, l.b_im_y, l.ky);
    if constexpr (Filtered) {
      // Faded lanes keep their sums as they are (as when the whole batch skipped the train above).
      const auto live = weight > 0.0f;
      p.height = simd::select(live, p.height + weight * h, p.height);
      p.grad_x = simd::select(live, p.grad_x + weight * gx, p.grad_x);
      p.grad_y = simd::select(live, p.grad_y + weight * gy, p.grad_y);
    } else {
      p.height = p.height + h;
      p.grad_x = p.grad_x + gx;
      p.grad_y = p.grad_y + gy;
    }
  }
  return p;
}

template <class A>
void train_grid_eval(const TrainGridFrame& f, const float* x, const float* y, std::size_t n,
                     GerstnerOutput out) noexcept {
  eval_height_field<A>(x, y, n, out, [&](simd::vfloat<A> px, simd::vfloat<A> py) {
    return train_grid_point<A, false>(f, px, py, nullptr, nullptr);
  });
}

template <class A>
void train_grid_eval_filtered(const TrainGridFrame& f, const float* x, const float* y, std::size_t n,
                              const NodeFootprint& footprint, GerstnerOutput out, float* slope_variance) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const simd::vfloat<A> px = b.load(x), py = b.load(y);
    const FootprintLanes<A> lanes = footprint_lanes<A>(footprint, px, py);
    simd::vfloat<A> variance(0.0f);
    const HeightFieldPoint<A> p = train_grid_point<A, true>(f, px, py, &lanes, &variance);
    b.store(out.height, p.height);
    b.store(out.grad_x, p.grad_x);
    b.store(out.grad_y, p.grad_y);
    b.store(slope_variance, variance);
  });
}

}  // namespace houle::detail
