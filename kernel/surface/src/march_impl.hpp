// The packet ray marcher, written once for every width (included by surface_isa.cpp; march.cpp uses
// the scalar instantiation for march_f). See houle/surface/march.hpp for the method.
//
// Determinism: a lane's result depends only on its own ray. Lanes that are done keep their state
// through selects; branches on any() only skip work no active lane needs. Only +, -, *, simd::div,
// comparisons, selects, exact float<->int conversions and loads are used (min/max are written as
// selects so that signed zeros and NaN behave as in the scalar path), so every ISA gives the scalar bits.
#pragma once
#include <cstddef>
#include <cstdint>

#include "capillary_impl.hpp"
#include "houle/surface/march.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/exp.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "march_context.hpp"

// The per-sample helpers are forced inline: out of line, their lane structs go through memory.
#define HOULE_MARCH_INLINE inline __attribute__((always_inline))

namespace houle::detail {

// ---- Small lane helpers (templates on A: nothing here is emitted outside an ISA's own symbols) ----

template <class A>
using MarchIndex = simd::vint<A>;

/// How many of the masks holds(0) .. holds(n - 1) hold in each lane, as two sums taken in turn: each
/// half as long a chain of dependent additions (of small integers: exact in any order).
template <class A, class Holds>
HOULE_MARCH_INLINE simd::vfloat<A> count_holding(std::uint32_t n, Holds holds) {
  using V = simd::vfloat<A>;
  V even(0.0f), odd(0.0f);
  for (std::uint32_t i = 0; i < n; i += 2) {
    even = even + simd::select(holds(i), V(1.0f), V(0.0f));
    if (i + 1 < n) odd = odd + simd::select(holds(i + 1), V(1.0f), V(0.0f));
  }
  return even + odd;
}

/// log2(x) for x in [1e-30, 1e30] (clamped), absolute error < 2e-6: exponent from the bits, then
/// 2/ln2 atanh(s), s = (m - 1)/(m + 1), m in [1, 2), as an odd series in s (|s| <= 1/3).
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> march_log2(simd::vfloat<A> x) {
  using V = simd::vfloat<A>;
  x = simd::min_as_std(V(1e30f), simd::max_as_std(V(1e-30f), x));  // NaN too
  const MarchIndex<A> bits = simd::bitcast_to_int(x);  // x > 0: the sign bit is clear
  const V e = simd::to_float_exact((bits >> 23) - MarchIndex<A>(127));
  const V m = simd::bitcast_to_float((bits & MarchIndex<A>(0x007fffff)) | MarchIndex<A>(0x3f800000));
  const V s = simd::div(m - 1.0f, m + 1.0f);
  const V s2 = s * s;
  // 2/ln 2 times 1, 1/3, 1/5, 1/7, 1/9, 1/11.
  const V p = 2.8853900817779268f +
              s2 * (0.9617966939259756f +
                    s2 * (0.5770780163555854f + s2 * (0.4121985831111324f + s2 * (0.3205988979753252f + s2 * 0.2623081892525388f))));
  return e + s * p;
}

// ---- The surface as the marcher samples it ----

/// Where one level is read at a point: node (i, j) offset and the fractions inside the cell.
template <class A>
struct GridTap {
  MarchIndex<A> node;
  simd::vfloat<A> fu, fv;
  simd::vfloat<A> iu, iv;  ///< cell indices (floats)
};

template <class A>
HOULE_MARCH_INLINE GridTap<A> grid_tap(const MarchContext& c, simd::vfloat<A> px, simd::vfloat<A> py, simd::vfloat<A> ox,
                           simd::vfloat<A> oy, simd::vfloat<A> inv_cell, simd::vfloat<A> node_base) {
  using V = simd::vfloat<A>;
  const V n(c.cells), last(c.cells - 1.0f);
  V u = (px - ox) * inv_cell, v = (py - oy) * inv_cell;
  // Inside the grid by construction (reach); the clamps keep rounding, far lanes and NaN in bounds.
  u = simd::min_as_std(n, simd::max_as_std(V(0.0f), u));
  v = simd::min_as_std(n, simd::max_as_std(V(0.0f), v));
  V iu = simd::floor_exact(u), iv = simd::floor_exact(v);
  iu = simd::min_as_std(last, iu);
  iv = simd::min_as_std(last, iv);
  GridTap<A> t;
  t.node = simd::to_int_exact(node_base + iv * c.stride_f + iu);
  t.fu = u - iu;
  t.fv = v - iv;
  t.iu = iu;
  t.iv = iv;
  return t;
}

template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> bilinear(const float* field, std::size_t stride, const GridTap<A>& t) {
  using V = simd::vfloat<A>;
  V h00, h10, h01, h11;
  simd::gather_adjacent(field, t.node, h00, h10);
  simd::gather_adjacent(field + stride, t.node, h01, h11);
  const V a = h00 + t.fu * (h10 - h00), b = h01 + t.fu * (h11 - h01);
  return a + t.fv * (b - a);
}

/// The height, bilinear as above, from the height pairs: two 64-bit gathers instead of four.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> bilinear_height(const MarchContext& c, const GridTap<A>& t) {
  using V = simd::vfloat<A>;
  V h00, h10, h01, h11;
  simd::gather_pair(c.height_pairs, t.node, h00, h10);
  simd::gather_pair(c.height_pairs + 2 * c.stride, t.node, h01, h11);
  const V a = h00 + t.fu * (h10 - h00), b = h01 + t.fu * (h11 - h01);
  return a + t.fv * (b - a);
}

/// The level read at a point: level l for reach_{l-1} < r <= reach_l, r the Chebyshev distance to the
/// centre; beyond the last reach, the far plane. (The SurfaceFrame morphs each level's outer band into
/// the next level, so one level is read per sample and H is still continuous.)
template <class A>
struct Located {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  V level;     ///< index of the level read (the last one for far lanes)
  M far;       ///< beyond the last level: the far plane
  V ox, oy;    ///< the level's origin
  V scale;     ///< 2^level
  GridTap<A> tap;
};

template <class A>
HOULE_MARCH_INLINE Located<A> locate(const MarchContext& c, simd::vfloat<A> px, simd::vfloat<A> py) {
  using V = simd::vfloat<A>;
  Located<A> s;
  const V r = simd::max_as_std(simd::abs(px - c.centre_x), simd::abs(py - c.centre_y));
  // The level is the number of reaches below r (they grow with the level); its origin is read from the
  // little tables, through a permute of two registers on AVX2 and AVX-512 (a chain of two selects per
  // level was 4 % more of march_rays' instructions on AVX2, callgrind).
  const V level = count_holding<A>(c.levels - 1, [&](std::uint32_t k) { return r > c.level_reach[k]; });
  const MarchIndex<A> l = simd::to_int_exact(level);
  s.ox = simd::gather_window(c.level_origin_x, l);
  s.oy = simd::gather_window(c.level_origin_y, l);
  s.far = r > c.level_reach[c.levels - 1];
  s.level = level;
  s.scale = simd::pow2_exact(level);
  s.tap = grid_tap<A>(c, px, py, s.ox, s.oy, c.inv_cell0 * simd::pow2_exact(V(0.0f) - level), level * c.level_floats);
  return s;
}

/// A field (height, grad_x, grad_y or slope_variance) of the grid at a located point; `far_value` beyond the levels.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> grid_field(const MarchContext& c, const float* field, const Located<A>& s,
                                              float far_value) {
  return simd::select(s.far, simd::vfloat<A>(far_value), bilinear<A>(field, c.stride, s.tap));
}

/// The grid's height at a located point; the far plane beyond the levels.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> grid_height(const MarchContext& c, const Located<A>& s) {
  return simd::select(s.far, simd::vfloat<A>(c.far_height), bilinear_height<A>(c, s.tap));
}

/// Bounds valid from the point along the ray up to s_box (m along the ray).
template <class A>
struct StepBounds {
  simd::vfloat<A> h_min, h_max, slope_x, slope_y, s_box;
};

/// The tile bounds last gathered, per lane, and which tile they belong to (-1: none yet).
template <class A>
struct TileCache {
  simd::vfloat<A> key = simd::vfloat<A>(-1.0f);  // (not braces: a batch's braces are an initializer list)
  StepBounds<A> bounds = {simd::vfloat<A>(0.0f), simd::vfloat<A>(0.0f), simd::vfloat<A>(0.0f), simd::vfloat<A>(0.0f),
                          simd::vfloat<A>(0.0f)};
};

template <class A>
HOULE_MARCH_INLINE StepBounds<A> step_bounds(const MarchContext& c, const Located<A>& s, simd::vfloat<A> px,
                                              simd::vfloat<A> py, simd::vfloat<A> dx, simd::vfloat<A> dy,
                                              simd::vfloat<A> inv_dx, simd::vfloat<A> inv_dy, simd::vmask<A> active,
                                              TileCache<A>& cache) {
  using V = simd::vfloat<A>;
  const V big(1e30f);
  const V ti = simd::floor_exact(s.tap.iu * c.inv_tile_cells), tj = simd::floor_exact(s.tap.iv * c.inv_tile_cells);
  const V key = s.level * c.level_tiles + tj * c.tiles_per_side + ti;
  // A ray takes several steps per tile: gather only when some active lane has moved to another tile
  // (lanes that have not get the same values again, so the result does not depend on the packet).
  if (simd::any(active & (key != cache.key))) {
    const MarchIndex<A> k = simd::to_int_exact(key);
    cache.key = key;
    cache.bounds.h_min = simd::gather(c.tile_min, k);
    cache.bounds.h_max = simd::gather(c.tile_max, k);
    cache.bounds.slope_x = simd::gather(c.tile_slope_x, k);
    cache.bounds.slope_y = simd::gather(c.tile_slope_y, k);
  }
  StepBounds<A> b = cache.bounds;
  // The tile, clipped to the level's reach (beyond it a coarser level's bounds apply).
  const V tile = c.tile_size0 * s.scale, reach = c.reach0 * s.scale;  // exact: powers of two
  const V x0 = s.ox + ti * tile, y0 = s.oy + tj * tile;
  const V x_lo = simd::max_as_std(x0, c.centre_x - reach), x_hi = simd::min_as_std(x0 + tile, c.centre_x + reach);
  const V y_lo = simd::max_as_std(y0, c.centre_y - reach), y_hi = simd::min_as_std(y0 + tile, c.centre_y + reach);
  // The side the ray leaves by (none when it does not move along the axis).
  const V sx = simd::select(dx == 0.0f, big, (simd::select(dx > 0.0f, x_hi, x_lo) - px) * inv_dx);
  const V sy = simd::select(dy == 0.0f, big, (simd::select(dy > 0.0f, y_hi, y_lo) - py) * inv_dy);
  b.s_box = simd::min_as_std(sx, sy);
  if (simd::any(s.far)) {
    // Beyond the last level: the flat far plane if the ray moves away from the grids for good (it is
    // outside the last reach on an axis along which it does not come back), else the global bounds.
    const V R(c.level_reach[c.levels - 1]);
    const V rx = px - c.centre_x, ry = py - c.centre_y;
    const auto away = ((rx > R) & (dx >= 0.0f)) | ((rx < -R) & (dx <= 0.0f)) | ((ry > R) & (dy >= 0.0f)) |
                      ((ry < -R) & (dy <= 0.0f));
    const V fh(c.far_height);
    b.h_min = simd::select(s.far, simd::select(away, fh, V(c.global.h_min)), b.h_min);
    b.h_max = simd::select(s.far, simd::select(away, fh, V(c.global.h_max)), b.h_max);
    b.slope_x = simd::select(s.far, simd::select(away, V(0.0f), V(c.global.slope_x)), b.slope_x);
    b.slope_y = simd::select(s.far, simd::select(away, V(0.0f), V(c.global.slope_y)), b.slope_y);
    b.s_box = simd::select(s.far, big, b.s_box);
  }
  return b;
}

// ---- Capillary noise: level from the footprint, bounds per level ----

/// level = clamp(level_offset + (log2 sin_grazing - log2 footprint_width) / log2 k, 0, n_max); `ray_offset`
/// holds the per-ray part level_offset + log2(sin) / log2 k.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> noise_level(const MarchContext& c, simd::vfloat<A> ray_offset, simd::vfloat<A> cone) {
  using V = simd::vfloat<A>;
  V l = ray_offset - march_log2<A>(cone) * c.inv_log2_lacunarity;
  return simd::min_as_std(V(c.max_level), simd::max_as_std(V(0.0f), l));
}

/// Height and slope bounds of the noise at a sample whose cone width is `cone_per_sin` times the
/// ray's sin(grazing): octave i counts while it can have weight (level > i), i.e. while the footprint
/// is below its threshold (octave_cone, widened a little so that rounding of the level never leaves
/// an octave out). Both fall as the ray goes on, so they hold for the rest of a step. No logarithm.
/// The thresholds fall with i, so the octaves that count are the first n: the bounds are the sums
/// of the first n shares, looked up (the count is a sum of small integers, exact in any order).
template <class A>
HOULE_MARCH_INLINE void noise_bounds(const MarchContext& c, simd::vfloat<A> cone_per_sin, simd::vfloat<A>& height,
                                     simd::vfloat<A>& slope) {
  const MarchIndex<A> n = simd::to_int_exact(
      count_holding<A>(c.octaves, [&](std::uint32_t i) { return cone_per_sin < c.octave_cone[i]; }));
  height = simd::gather_window(c.octaves_height, n);
  slope = simd::gather_window(c.octaves_slope, n);
}

/// The two uses of capillary_impl.hpp (the only coupling to it): height alone while marching, height
/// and gradient at the hit.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> noise_height(const MarchContext& c, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> level) {
  return capillary_point<A, false>(*c.noise, c.noise_pairs, x, y, level).height;
}
template <class A>
HOULE_MARCH_INLINE CapillaryPoint<A> noise_point(const MarchContext& c, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> level) {
  return capillary_point<A, true>(*c.noise, c.noise_pairs, x, y, level);
}

/// Per-ray constants.
template <class A>
struct MarchRay {
  using V = simd::vfloat<A>;
  V ox, oy, oz, dx, dy, dz, adx, ady, adz, inv_dx, inv_dy, level_offset, inv_sin;
  V horizontal;  ///< |(dx, dy)|: the noise's slope bound is on its gradient's length, not per axis
};

/// Per-ray constants. Non-finite rays (x - x != 0 for inf and NaN) become inert (`finite` false).
template <class A>
inline MarchRay<A> make_march_ray(const MarchContext& c, simd::vfloat<A> ox, simd::vfloat<A> oy, simd::vfloat<A> oz,
                                  simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> dz, simd::vmask<A>& finite) {
  using V = simd::vfloat<A>;
  const V zero(0.0f), one(1.0f);
  finite = ((ox - ox) == zero) & ((oy - oy) == zero) & ((oz - oz) == zero) & ((dx - dx) == zero) &
           ((dy - dy) == zero) & ((dz - dz) == zero);
  MarchRay<A> r;
  r.ox = simd::select(finite, ox, zero);
  r.oy = simd::select(finite, oy, zero);
  r.oz = simd::select(finite, oz, zero);
  // Components below 1e-20 are taken as 0: their reciprocals stay finite and their exits infinite.
  r.dx = simd::select(finite & (simd::abs(dx) >= 1e-20f), dx, zero);
  r.dy = simd::select(finite & (simd::abs(dy) >= 1e-20f), dy, zero);
  r.dz = simd::select(finite & (simd::abs(dz) >= 1e-20f), dz, zero);
  r.adx = simd::abs(r.dx);
  r.ady = simd::abs(r.dy);
  r.adz = simd::abs(r.dz);
  r.inv_dx = simd::div(one, simd::select(r.dx == zero, one, r.dx));
  r.inv_dy = simd::div(one, simd::select(r.dy == zero, one, r.dy));
  r.horizontal = simd::sqrt(r.dx * r.dx + r.dy * r.dy);
  r.level_offset = zero;
  r.inv_sin = zero;
  if (c.noise != nullptr) {
    const V sin_grazing = simd::select(r.adz > 1e-3f, r.adz, V(1e-3f));
    r.level_offset = c.level_offset + march_log2<A>(sin_grazing) * c.inv_log2_lacunarity;
    r.inv_sin = simd::div(one, sin_grazing);
  }
  return r;
}

/// The full (noise included) f at distance t, times sigma.
template <class A>
HOULE_MARCH_INLINE simd::vfloat<A> full_g(const MarchContext& c, const MarchRay<A>& r, simd::vfloat<A> t,
                                          simd::vfloat<A> sigma) {
  using V = simd::vfloat<A>;
  const V px = r.ox + t * r.dx, py = r.oy + t * r.dy, pz = r.oz + t * r.dz;
  const Located<A> s = locate<A>(c, px, py);
  V f = pz - grid_height<A>(c, s);
  if (c.noise != nullptr) {
    const V level = noise_level<A>(c, r.level_offset, c.cone_width + t * c.pixel_angle);
    f = f - noise_height<A>(c, px, py, level);
  }
  return sigma * f;
}

template <class A>
struct MarchResult {
  using V = simd::vfloat<A>;
  V t, x, y, z, grad_x, grad_y, level, status, evaluations, slope_variance;
};

/// One packet's march in progress: its rays, where they are, and the bracket [a, b] of the crossing
/// each found. A packet is stepped by march_step until none of its lanes is active, then refined.
template <class A>
struct MarchState {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  MarchRay<A> r;
  V t_end, t_out, t, sigma, t_prev, g_prev, a, ga, b, gb, evaluations, side;
  M active, crossed;
  TileCache<A> tiles;
};

template <class A>
HOULE_MARCH_INLINE MarchState<A> march_start(const MarchContext& c, simd::vfloat<A> ox, simd::vfloat<A> oy,
                                             simd::vfloat<A> oz, simd::vfloat<A> dx, simd::vfloat<A> dy,
                                             simd::vfloat<A> dz, simd::vfloat<A> t_max) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f), big(1e30f);
  MarchState<A> m;
  M finite(false);
  m.r = make_march_ray<A>(c, ox, oy, oz, dx, dy, dz, finite);
  const MarchRay<A>& r = m.r;
  const V inv_dz = simd::div(one, simd::select(r.dz == zero, one, r.dz));

  // The ray's end and its interval in the slab.
  m.t_end = simd::max_as_std(zero, simd::min_as_std(V(c.max_distance), t_max));  // NaN: max_distance
  const V t_top = (c.z_hi - r.oz) * inv_dz, t_bottom = (c.z_lo - r.oz) * inv_dz;
  const M inside = (r.oz >= c.z_lo) & (r.oz <= c.z_hi);
  const V t_enter = simd::select(r.dz > zero, t_bottom, simd::select(r.dz < zero, t_top, simd::select(inside, zero, big)));
  const V t_exit = simd::select(r.dz > zero, t_top, simd::select(r.dz < zero, t_bottom, simd::select(inside, big, zero)));
  const V t_in = simd::max_as_std(t_enter, zero);
  m.t_out = simd::min_as_std(t_exit, m.t_end);
  m.active = finite & (t_in < m.t_out);
  m.t = simd::select(m.active, t_in, zero);
  m.sigma = one;
  m.t_prev = m.t;
  m.g_prev = m.a = m.ga = m.b = m.gb = m.evaluations = m.side = zero;
  m.crossed = M(false);
  return m;
}

/// Step `it` (0 for the first) of a packet with active lanes: a sample, the crossing test, the step.
template <class A>
HOULE_MARCH_INLINE void march_step(const MarchContext& c, MarchState<A>& m, std::int32_t it) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f), big(1e30f);
  const bool noise = c.noise != nullptr;
  const MarchRay<A>& r = m.r;
  const V t = m.t;
  const V px = r.ox + t * r.dx, py = r.oy + t * r.dy, pz = r.oz + t * r.dz;
  const Located<A> s = locate<A>(c, px, py);
  const V f_grid = pz - grid_height<A>(c, s);
  const V cone = c.cone_width + t * c.pixel_angle;
  // g: sigma f when it is known; outside the noise envelope a bound with the right sign.
  V g, g_env, noise_h = zero, noise_s = zero, level_term = zero;
  M near(true);
  if (noise) {
    noise_bounds<A>(c, cone * r.inv_sin, noise_h, noise_s);
    near = simd::abs(f_grid) <= noise_h;
    V f = f_grid;
    if (simd::any(m.active & near)) {
      // Inside the envelope: the noise itself, at the sample's level.
      const V level = noise_level<A>(c, r.level_offset, cone);
      f = simd::select(near, f_grid - noise_height<A>(c, px, py, level), f_grid);
      // The level falls along the ray; its change moves the noise by at most this much per m.
      level_term = simd::div(V(c.level_rate * c.pixel_angle), simd::max_as_std(cone, V(1e-20f)));
    }
    if (it == 0) m.sigma = simd::select(f >= zero, one, V(-1.0f));
    g_env = m.sigma * f_grid - noise_h;
    g = simd::select(near, m.sigma * f, g_env);
  } else {
    if (it == 0) m.sigma = simd::select(f_grid >= zero, one, V(-1.0f));
    g = m.sigma * f_grid;
    g_env = g;
  }
  m.evaluations = m.evaluations + simd::select(m.active, one, zero);

  const M cross_now = m.active & (g <= zero);
  m.a = simd::select(cross_now, m.t_prev, m.a);
  m.ga = simd::select(cross_now, m.g_prev, m.ga);
  m.b = simd::select(cross_now, t, m.b);
  m.gb = simd::select(cross_now, g, m.gb);
  m.crossed = m.crossed | cross_now;
  m.active = m.active & !cross_now;
  m.active = m.active & (t < m.t_out);  // the sample at t_out was the last
  if (!simd::any(m.active)) return;

  // The step: the largest distance that provably holds no crossing, within the bounds' box, but at
  // least delta.
  const StepBounds<A> bd = step_bounds<A>(c, s, px, py, r.dx, r.dy, r.inv_dx, r.inv_dy, m.active, m.tiles);
  const V lip = simd::max_as_std(r.adz + bd.slope_x * r.adx + bd.slope_y * r.ady, V(1e-30f));
  V safe = simd::select(g_env > zero, simd::div(g_env, lip), zero);
  if (noise) {
    const V lip_full = lip + noise_s * r.horizontal + level_term;
    safe = simd::max_as_std(safe, simd::select(near & (g > zero), simd::div(g, lip_full), zero));
  }
  const V top = simd::select(m.sigma > zero, bd.h_max + noise_h, bd.h_min - noise_h);
  const V gap = m.sigma * (pz - top), rate = zero - m.sigma * r.dz;
  safe = simd::max_as_std(safe, simd::select(gap > zero, simd::select(rate > zero, simd::div(gap, rate), big), zero));
  const V delta = simd::max_as_std(c.step_fraction * cone, V(c.min_step));
  const V step = simd::max_as_std(simd::min_as_std(safe, bd.s_box + 0.125f * delta), delta);
  m.t_prev = simd::select(m.active, t, m.t_prev);
  m.g_prev = simd::select(m.active, g, m.g_prev);
  m.t = simd::select(m.active, simd::min_as_std(t + step, m.t_out), t);
}

/// One Illinois iteration on [a, b] of a packet with crossed lanes: g(a) > 0 >= g(b) (a == b when the
/// ray starts on the surface).
template <class A>
HOULE_MARCH_INLINE void refine_step(const MarchContext& c, MarchState<A>& m) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f);
  const V den = m.ga - m.gb;
  V x = simd::select(den > zero, m.a + (m.b - m.a) * simd::div(m.ga, simd::select(den > zero, den, one)), m.a);
  x = simd::max_as_std(simd::min_as_std(x, m.b), m.a);
  const V gx = full_g<A>(c, m.r, x, m.sigma);
  const M rb = m.crossed & (gx <= zero), ra = m.crossed & !(gx <= zero);
  m.ga = simd::select(rb & (m.side > zero), m.ga * 0.5f, m.ga);  // b kept twice: halve the stale end's value
  m.gb = simd::select(ra & (m.side < zero), m.gb * 0.5f, m.gb);
  m.b = simd::select(rb, x, m.b);
  m.gb = simd::select(rb, gx, m.gb);
  m.a = simd::select(ra, x, m.a);
  m.ga = simd::select(ra, gx, m.ga);
  m.side = simd::select(rb, one, simd::select(ra, V(-1.0f), m.side));  // +1: b was replaced last, -1: a was
  m.evaluations = m.evaluations + simd::select(m.crossed, one, zero);
}

/// The hit of a packet whose march and refinement are done (lanes still active ran out of steps), written
/// in place (a returned result was copied out whole: 1-2 % of the march on Zen 3).
template <class A>
HOULE_MARCH_INLINE void march_result(const MarchContext& c, MarchState<A>& m, MarchResult<A>& out) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f);
  const bool noise = c.noise != nullptr;
  const MarchRay<A>& r = m.r;
  const M crossed = m.crossed, exhausted = m.active;
  V t_hit = m.b;
  if (simd::any(crossed)) {
    const V den = m.ga - m.gb;
    t_hit = simd::select(den > zero, m.a + (m.b - m.a) * simd::div(m.ga, simd::select(den > zero, den, one)), m.a);
    t_hit = simd::max_as_std(simd::min_as_std(t_hit, m.b), m.a);
  }

  out.t = simd::select(crossed, t_hit, simd::select(exhausted, m.t, m.t_end));
  out.x = r.ox + out.t * r.dx;
  out.y = r.oy + out.t * r.dy;
  out.z = r.oz + out.t * r.dz;
  out.grad_x = zero;
  out.grad_y = zero;
  out.level = zero;
  out.slope_variance = zero;
  if (simd::any(crossed)) {
    // The eq. 8 normal: gradients add. Grid gradients are interpolated (and morphed) like the heights.
    const Located<A> s = locate<A>(c, out.x, out.y);
    V gx = grid_field<A>(c, c.grad_x, s, 0.0f);
    V gy = grid_field<A>(c, c.grad_y, s, 0.0f);
    if (noise) {
      const V level = noise_level<A>(c, r.level_offset, c.cone_width + out.t * c.pixel_angle);
      const CapillaryPoint<A> n = noise_point<A>(c, out.x, out.y, level);
      gx = gx + n.grad_x;
      gy = gy + n.grad_y;
      out.level = simd::select(crossed, level, zero);
    }
    out.grad_x = simd::select(crossed, gx, zero);
    out.grad_y = simd::select(crossed, gy, zero);
    out.slope_variance = simd::select(crossed, grid_field<A>(c, c.slope_variance, s, 0.0f), zero);
    m.evaluations = m.evaluations + simd::select(crossed, one, zero);
  }
  out.status = simd::select(crossed, simd::select(m.sigma > zero, one, V(2.0f)), simd::select(exhausted, V(3.0f), zero));
  out.evaluations = m.evaluations;
}

/// N packets marched together: a step spends most of its time waiting for its gathers, and the other
/// packets' steps fill that wait (docs/design.md 10). Each packet takes exactly the steps and
/// iterations it takes alone, so its lanes get the bits they get alone.
template <class A, std::size_t N>
HOULE_MARCH_INLINE void march_packets(const MarchContext& c, MarchState<A> (&m)[N], MarchResult<A> (&out)[N]) {
  for (std::int32_t it = 0; it < c.max_steps; ++it) {
    bool stepped = false;
    for (std::size_t k = 0; k < N; ++k) {
      if (!simd::any(m[k].active)) continue;
      march_step<A>(c, m[k], it);
      stepped = true;
    }
    if (!stepped) break;
  }
  for (std::int32_t k = 0; k < c.refine_iterations; ++k) {
    for (std::size_t p = 0; p < N; ++p) {
      if (simd::any(m[p].crossed)) refine_step<A>(c, m[p]);
    }
  }
  for (std::size_t p = 0; p < N; ++p) march_result<A>(c, m[p], out[p]);
}

/// n rays in packets of the ISA's width, two at a time (simd::for_batch_pairs). Padding lanes of the
/// tail: a ray going up from above the slab, done before the first sample.
template <class A>
void march_rays(const MarchContext& c, const MarchRays& rays, std::size_t n, const MarchHits& hits) noexcept {
  const auto start = [&](const auto& b) HOULE_BATCH_BODY {
    const simd::vfloat<A> t_max = rays.t_max != nullptr ? b.load(rays.t_max) : simd::vfloat<A>(c.max_distance);
    return march_start<A>(c, b.load(rays.ox, c.centre_x), b.load(rays.oy, c.centre_y), b.load(rays.oz, c.z_hi + 1.0f),
                          b.load(rays.dx), b.load(rays.dy), b.load(rays.dz, 1.0f), t_max);
  };
  const auto store = [&](const auto& b, const MarchResult<A>& m) HOULE_BATCH_BODY {
    if (hits.t != nullptr) b.store(hits.t, m.t);
    if (hits.x != nullptr) b.store(hits.x, m.x);
    if (hits.y != nullptr) b.store(hits.y, m.y);
    if (hits.z != nullptr) b.store(hits.z, m.z);
    if (hits.grad_x != nullptr) b.store(hits.grad_x, m.grad_x);
    if (hits.grad_y != nullptr) b.store(hits.grad_y, m.grad_y);
    if (hits.noise_level != nullptr) b.store(hits.noise_level, m.level);
    if (hits.slope_variance != nullptr) b.store(hits.slope_variance, m.slope_variance);
    if (hits.status != nullptr) {
      b.store(hits.status, m.status, [](float s) { return static_cast<MarchStatus>(static_cast<std::uint8_t>(s)); });
    }
    if (hits.evaluations != nullptr) {
      b.store(hits.evaluations, m.evaluations, [](float e) { return static_cast<std::uint32_t>(e); });
    }
  };
  simd::for_batch_pairs<A>(
      n,
      [&](const auto& b0, const auto& b1) HOULE_BATCH_BODY {
        MarchState<A> m[2] = {start(b0), start(b1)};
        MarchResult<A> out[2];
        march_packets<A, 2>(c, m, out);
        store(b0, out[0]);
        store(b1, out[1]);
      },
      [&](const auto& b) HOULE_BATCH_BODY {
        MarchState<A> m[1] = {start(b)};
        MarchResult<A> out[1];
        march_packets<A, 1>(c, m, out);
        store(b, out[0]);
      });
}

}  // namespace houle::detail

#undef HOULE_MARCH_INLINE
