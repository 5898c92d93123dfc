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

/// Where one train's grid is read at the points, and the reads. Off the grid the nearest point of its
/// edge goes on along its wave vector: phi grows by k . (p - edge point), the other fields stay its own
/// (docs/physics.md 2.8), so the sea beyond the domain continues the sea at its edge. Without a grid the
/// train is its far field, phi = far_kx x + far_ky y (the caller subtracts the far field's constant,
/// which differs between the probe and the frame). The fields come in two parts, so that a train the
/// footprint fades out everywhere reads only the first.
template <class A>
class TrainGridTap {
 public:
  using V = simd::vfloat<A>;

  // Forced inline: out of line its lanes went through memory (2-3 % of a frame's samples).
  __attribute__((always_inline)) TrainGridTap(const TrainGrid& g, V x, V y) : g_(g), x_(x), y_(y) {
    if (g.nx < 2) return;
    const V zero(0.0f);
    inv_cell_ = 1.0f / g.cell;
    const float last_x = float(g.nx - 1), last_y = float(g.ny - 1);
    const V gx = (x - g.origin_x) * inv_cell_, gy = (y - g.origin_y) * inv_cell_;
    // Clamped to the grid; NaN reads node 0 (its lanes are NaN by the phase below).
    in_x_ = (gx >= 0.0f) & (gx <= last_x);
    in_y_ = (gy >= 0.0f) & (gy <= last_y);
    const V cx = simd::select(in_x_, gx, simd::select(gx > last_x, V(last_x), zero));
    const V cy = simd::select(in_y_, gy, simd::select(gy > last_y, V(last_y), zero));
    const V i = simd::min(simd::floor_exact(cx), V(last_x - 1.0f)), j = simd::min(simd::floor_exact(cy), V(last_y - 1.0f));
    u_ = cx - i;
    v_ = cy - j;
    n00_ = simd::to_int_exact(j) * simd::vint<A>(std::int32_t(g.nx)) + simd::to_int_exact(i);
    // Off the grid along an axis, the offset from the edge point along it (exactly 0 on the grid).
    off_x_ = simd::select(in_x_, zero, (gx - cx) * g.cell);
    off_y_ = simd::select(in_y_, zero, (gy - cy) * g.cell);
    // Along a row of the surface frame, a batch's cells often lie within a few nodes of each other:
    // then each corner comes from a window of the field (two loads and a permute), not a gather
    // (docs/design.md 10). The same values, so the same bits as the scalar path.
    if constexpr (simd::window_floats<A>() > 0) {
      std::int32_t lo, hi;
      simd::lane_range(n00_, lo, hi);
      const std::int64_t nodes = std::int64_t(g.nx) * g.ny;
      if (hi - lo + 1 < simd::window_floats<A>() && std::int64_t(lo) + std::int64_t(g.nx) + simd::window_floats<A>() <= nodes) {
        window_ = lo;
        // The next batches of a row read on along these two grid rows, in 14 streams per train that
        // the hardware's prefetchers do not follow: ask for what lies four cache lines ahead.
        const std::int64_t ahead = std::min<std::int64_t>(lo + 64, nodes - 1 - std::int64_t(g.nx));
        for (const float* q : {g.kx, g.ky, g.b_re, g.b_im, g.fold, g.lean, g.phi}) {
          __builtin_prefetch(q + ahead);
          __builtin_prefetch(q + ahead + g.nx);
        }
      }
    }
  }

  /// k, B and B's gradient: what the footprint's weight and the slope variance it drops need.
  void wave(TrainGridLanes<A>& r) const {
    const V zero(0.0f);
    if (g_.nx < 2) {
      r.kx = V(g_.far_kx), r.ky = V(g_.far_ky), r.b_re = V(g_.far_amplitude), r.b_im = zero;
      r.b_re_x = r.b_re_y = r.b_im_x = r.b_im_y = zero;
      return;
    }
    r.kx = field(g_.kx);
    r.ky = field(g_.ky);
    with_gradient(g_.b_re, r.b_re, r.b_re_x, r.b_re_y);
    with_gradient(g_.b_im, r.b_im, r.b_im_x, r.b_im_y);
  }
  /// phi, fold and lean (after wave(r): phi goes on along r's k off the grid).
  void shape(TrainGridLanes<A>& r) const {
    if (g_.nx < 2) {
      r.phi = x_ * g_.far_kx + y_ * g_.far_ky, r.fold = V(g_.far_fold), r.lean = V(g_.far_lean);
      return;
    }
    r.fold = field(g_.fold);
    r.lean = field(g_.lean);
    r.phi = field(g_.phi) + (r.kx * off_x_ + r.ky * off_y_);
  }

 private:
  struct Corners {
    V q00, q10, q01, q11;
  };
  Corners corners(const float* q) const {
    const std::size_t row = g_.nx;
    if constexpr (simd::window_floats<A>() > 0) {
      if (window_ >= 0) {
        const simd::vint<A> o = n00_ - simd::vint<A>(window_), o1 = o + simd::vint<A>(1);
        const float *w0 = q + window_, *w1 = w0 + row;
        return {simd::gather_window(w0, o), simd::gather_window(w0, o1), simd::gather_window(w1, o),
                simd::gather_window(w1, o1)};
      }
    }
    Corners c;
    simd::gather_adjacent(q, n00_, c.q00, c.q10);
    simd::gather_adjacent(q + row, n00_, c.q01, c.q11);
    return c;
  }
  V lerp2(const Corners& c) const {
    const V bottom = c.q00 + (c.q10 - c.q00) * u_, top = c.q01 + (c.q11 - c.q01) * u_;
    return bottom + (top - bottom) * v_;
  }
  V field(const float* q) const { return lerp2(corners(q)); }
  /// B and its derivatives in the cell (per metre); B is constant off the grid along a clamped axis.
  void with_gradient(const float* q, V& value, V& d_dx, V& d_dy) const {
    const V zero(0.0f);
    const Corners c = corners(q);
    value = lerp2(c);
    const V dx = ((c.q10 - c.q00) + ((c.q11 - c.q01) - (c.q10 - c.q00)) * v_) * inv_cell_;
    const V dy = ((c.q01 - c.q00) + ((c.q11 - c.q10) - (c.q01 - c.q00)) * u_) * inv_cell_;
    d_dx = simd::select(in_x_, dx, zero);
    d_dy = simd::select(in_y_, dy, zero);
  }

  const TrainGrid& g_;
  V x_, y_;
  // (Not braces: a batch's braces are an initializer list.)
  V u_ = V(0.0f), v_ = V(0.0f), off_x_ = V(0.0f), off_y_ = V(0.0f);
  simd::vint<A> n00_ = simd::vint<A>(0);
  simd::vmask<A> in_x_ = simd::vmask<A>(false), in_y_ = simd::vmask<A>(false);
  float inv_cell_ = 1.0f;
  std::int32_t window_ = -1;  // the first node of the window, or -1: gather
};

/// One train's fields at the points (TrainGridTap).
template <class A>
inline TrainGridLanes<A> train_grid_lanes(const TrainGrid& g, simd::vfloat<A> x, simd::vfloat<A> y) {
  const TrainGridTap<A> tap(g, x, y);
  TrainGridLanes<A> r;
  tap.wave(r);
  tap.shape(r);
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
  const V p = simd::sqrt(simd::max_as_std(pixel, grid));
  V u = V(2.0f) - p * 0.318309886f;  // 1 / pi
  u = simd::min_as_std(V(1.0f), simd::max_as_std(V(0.0f), u));
  return u * u * (V(3.0f) - 2.0f * u);
}

/// Adds train t of the frame at the points, from its fields there (after wave() and shape()), to p;
/// filtered, weighted (footprint_weight), lanes of weight 0 left as they are. The part of the sum
/// that changes with the time: the kept path (train_grid_eval_filtered) runs it too.
template <class A, bool Filtered>
inline __attribute__((always_inline)) void add_train(const TrainGridFrame& f, std::uint32_t t,
                                                     const TrainGridLanes<A>& l, simd::vfloat<A> weight,
                                                     HeightFieldPoint<A>& p) {
  using V = simd::vfloat<A>;
  const V theta = l.phi - V(f.trains[t].nx < 2 ? f.far_phase[t] : f.time_phase[t]);
  V s, c;
  simd::sincos(theta, s, c);
  // w = B e^{i theta}; its derivative along an axis: e^{i theta} dB + i k w.
  const V w_re = l.b_re * c - l.b_im * s, w_im = l.b_re * s + l.b_im * c;
  const V delta = l.fold * w_re + l.lean * w_im;
  // The shape's phase shift is small but for the steepest waves: then the reduction can be skipped.
  V sd, cd;
  if (simd::all(simd::abs(delta) < 0.78f)) {
    simd::sincos_reduced(delta, sd, cd);
  } else {
    simd::sincos(delta, sd, cd);
  }
  const V slope = w_im * sd + w_re * cd;  // -d h / d delta
  const auto derivative = [&](V db_re, V db_im, V k) {
    const V dw_re = (db_re * c - db_im * s) - k * w_im, dw_im = (db_re * s + db_im * c) + k * w_re;
    return (dw_im * cd - dw_re * sd) - slope * (l.fold * dw_re + l.lean * dw_im);
  };
  const V h = w_im * cd - w_re * sd;
  const V gx = derivative(l.b_re_x, l.b_im_x, l.kx), gy = derivative(l.b_re_y, l.b_im_y, l.ky);
  if constexpr (Filtered) {
    // Faded lanes keep their sums as they are (as when the whole batch skips the train).
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

/// A train's footprint weight at the points and the slope variance it drops there, added to `variance`.
template <class A>
inline __attribute__((always_inline)) simd::vfloat<A> train_weight(const FootprintLanes<A>& footprint,
                                                                   const TrainGridLanes<A>& l,
                                                                   simd::vfloat<A>& variance) {
  using V = simd::vfloat<A>;
  const V weight = footprint_weight<A>(footprint, l.kx, l.ky);
  const V b2 = l.b_re * l.b_re + l.b_im * l.b_im, k2 = l.kx * l.kx + l.ky * l.ky;
  variance = variance + (V(1.0f) - weight * weight) * (b2 * k2 * 0.25f);
  return weight;
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
    const TrainGridTap<A> tap(f.trains[t], x, y);
    TrainGridLanes<A> l;
    tap.wave(l);
    V weight(1.0f);
    if constexpr (Filtered) {
      weight = train_weight<A>(*footprint, l, *variance);
      if (!simd::any(weight > 0.0f)) continue;  // faded everywhere here: nothing to add
    }
    tap.shape(l);
    add_train<A, Filtered>(f, t, l, weight, p);
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

/// The kept path's fields per train, each a vector per batch of points.
inline constexpr int kept_train_floats = int(train_grid_keep_floats(1));

template <class A>
void train_grid_eval_filtered(const TrainGridFrame& f, const float* x, const float* y, std::size_t n,
                              const NodeFootprint& footprint, GerstnerOutput out, float* slope_variance,
                              TrainGridKeep keep) noexcept {
  using V = simd::vfloat<A>;
  if (keep.data == nullptr) {
    simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
      const V px = b.load(x), py = b.load(y);
      const FootprintLanes<A> lanes = footprint_lanes<A>(footprint, px, py);
      V variance(0.0f);
      const HeightFieldPoint<A> p = train_grid_point<A, true>(f, px, py, &lanes, &variance);
      b.store(out.height, p.height);
      b.store(out.grad_x, p.grad_x);
      b.store(out.grad_y, p.grad_y);
      b.store(slope_variance, variance);
    });
    return;
  }
  // Kept: the fields, which change neither with the time nor with the viewer, are read back (or read
  // from the grids and written first); the weights and the time's part follow as above, through the
  // same operations on the same values: the same bits.
  constexpr std::size_t W = simd::width<A>;
  const std::size_t per_batch = train_grid_keep_floats(f.count) * W;
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const V px = b.load(x), py = b.load(y);
    float* q = keep.data + b.index() / W * per_batch;
    // The kept fields stream in at 44 bytes a node and train, and the hardware's prefetchers left the
    // fill waiting on them (docs/design.md 10): ask for the batch after next.
    // (An address, not a pointer: past the last run it lies beyond the keep, where a prefetch is harmless.)
    const std::uintptr_t ahead = reinterpret_cast<std::uintptr_t>(q) + 2 * per_batch * sizeof(float);
    for (std::size_t line = 0; line < per_batch * sizeof(float); line += 64) {
      __builtin_prefetch(reinterpret_cast<const void*>(ahead + line));
    }
    if (!keep.kept) {
      for (std::uint32_t t = 0; t < f.count; ++t) {
        const TrainGridTap<A> tap(f.trains[t], px, py);
        TrainGridLanes<A> l;
        tap.wave(l);
        tap.shape(l);
        const V fields[kept_train_floats] = {l.phi,  l.b_re,   l.b_im,   l.kx,     l.ky,    l.fold,
                                             l.lean, l.b_re_x, l.b_re_y, l.b_im_x, l.b_im_y};
        for (int k = 0; k < kept_train_floats; ++k) simd::store<A>(q + (t * kept_train_floats + k) * W, fields[k]);
      }
    }
    const FootprintLanes<A> lanes = footprint_lanes<A>(footprint, px, py);
    V variance(0.0f);
    HeightFieldPoint<A> p{V(0.0f), V(0.0f), V(0.0f)};
    for (std::uint32_t t = 0; t < f.count; ++t) {
      const float* r = q + t * kept_train_floats * W;
      TrainGridLanes<A> l;
      l.kx = simd::load<A>(r + 3 * W);
      l.ky = simd::load<A>(r + 4 * W);
      l.b_re = simd::load<A>(r + W);
      l.b_im = simd::load<A>(r + 2 * W);
      const V weight = train_weight<A>(lanes, l, variance);
      if (!simd::any(weight > 0.0f)) continue;
      l.phi = simd::load<A>(r);
      l.fold = simd::load<A>(r + 5 * W);
      l.lean = simd::load<A>(r + 6 * W);
      l.b_re_x = simd::load<A>(r + 7 * W);
      l.b_re_y = simd::load<A>(r + 8 * W);
      l.b_im_x = simd::load<A>(r + 9 * W);
      l.b_im_y = simd::load<A>(r + 10 * W);
      add_train<A, true>(f, t, l, weight, p);
    }
    b.store(out.height, p.height);
    b.store(out.grad_x, p.grad_x);
    b.store(out.grad_y, p.grad_y);
    b.store(slope_variance, variance);
  });
}

}  // namespace houle::detail
