// The packet ray marcher, written once for every width (included by kernels_isa.cpp; march.cpp uses
// the scalar instantiation for march_f). See houle/kernel/march.hpp for the method.
//
// Determinism: a lane's result depends only on its own ray. Lanes that are done keep their state
// through selects; branches on any() only skip work no active lane needs. Only +, -, *, simd::div,
// comparisons, selects, exact float<->int conversions and loads are used (min/max are written as
// selects so that signed zeros and NaN behave as in the scalar path), so every ISA gives the scalar bits.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "capillary_impl.hpp"
#include "houle/kernel/march.hpp"
#include "houle/simd/simd.hpp"
#include "march_context.hpp"

namespace houle::detail {

// ---- Small lane helpers (templates on A: nothing here is emitted outside an ISA's own symbols) ----

template <class A>
struct MarchIndexType {
  using type = std::int32_t;
};
#if HOULE_SIMD_BATCHES
template <class A>
  requires(!std::is_same_v<A, simd::scalar>)
struct MarchIndexType<A> {
  using type = xsimd::batch<std::int32_t, A>;
};
#endif
template <class A>
using MarchIndex = typename MarchIndexType<A>::type;

/// Integral float in [0, 2^24) to an int32 lane: exact.
template <class A>
inline MarchIndex<A> march_index(simd::vfloat<A> x) {
#if HOULE_SIMD_BATCHES
#if defined(__AVX512F__)
  // xsimd's conversion goes through _mm512_cvttps_epi32, whose _mm512_undefined_epi32 trips gcc 12's
  // -Wuninitialized once inlined; the zero-masked form is the same instruction without it.
  if constexpr (std::is_base_of_v<xsimd::avx512f, A>) {
    return _mm512_maskz_cvttps_epi32(static_cast<__mmask16>(0xFFFF), x);
  } else
#endif
  if constexpr (!std::is_same_v<A, simd::scalar>) {
    return xsimd::batch_cast<std::int32_t>(x);
  } else
#endif
  {
    return static_cast<std::int32_t>(x);
  }
}

/// p[i] per lane (AVX2 / AVX-512 use their float gather instructions).
template <class A>
inline simd::vfloat<A> march_gather(const float* p, MarchIndex<A> i) {
#if HOULE_SIMD_BATCHES
  if constexpr (!std::is_same_v<A, simd::scalar>) {
    return simd::vfloat<A>::gather(p, i);
  } else
#endif
  {
    return p[i];
  }
}

template <class A>
inline simd::vfloat<A> vmin(simd::vfloat<A> a, simd::vfloat<A> b) {
  return simd::select(b < a, b, a);
}
template <class A>
inline simd::vfloat<A> vmax(simd::vfloat<A> a, simd::vfloat<A> b) {
  return simd::select(a < b, b, a);
}

/// floor of x in [0, 2^22): the rounding-by-addition of simd.hpp, then a correction.
template <class A>
inline simd::vfloat<A> march_floor(simd::vfloat<A> x) {
  using V = simd::vfloat<A>;
  const V r = simd::round_nearest(x);
  return r - simd::select(r > x, V(1.0f), V(0.0f));
}

/// log2(x) for x in [1e-30, 1e30] (clamped), absolute error < 2e-6: exponent from the bits, then
/// 2/ln2 atanh(s), s = (m - 1)/(m + 1), m in [1, 2), as an odd series in s (|s| <= 1/3).
template <class A>
inline simd::vfloat<A> march_log2(simd::vfloat<A> x) {
  using V = simd::vfloat<A>;
  x = simd::select(x > 1e-30f, x, V(1e-30f));  // NaN too
  x = simd::select(x < 1e30f, x, V(1e30f));
  V e, m;
#if HOULE_SIMD_BATCHES
  if constexpr (!std::is_same_v<A, simd::scalar>) {
    using I = xsimd::batch<std::int32_t, A>;
    const I bits = xsimd::bitwise_cast<I>(x);
    e = xsimd::batch_cast<float>((bits >> 23) - I(127));
    m = xsimd::bitwise_cast<V>((bits & I(0x007fffff)) | I(0x3f800000));
  } else
#endif
  {
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    e = static_cast<float>(static_cast<std::int32_t>(bits >> 23) - 127);
    const std::uint32_t mb = (bits & 0x007fffffu) | 0x3f800000u;
    std::memcpy(&m, &mb, sizeof m);
  }
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
inline GridTap<A> grid_tap(const MarchContext& c, simd::vfloat<A> px, simd::vfloat<A> py, simd::vfloat<A> ox,
                           simd::vfloat<A> oy, simd::vfloat<A> inv_cell, simd::vfloat<A> node_base) {
  using V = simd::vfloat<A>;
  const V n(c.cells), last(c.cells - 1.0f);
  V u = (px - ox) * inv_cell, v = (py - oy) * inv_cell;
  // Inside the grid by construction (reach); the clamps keep rounding, far lanes and NaN in bounds.
  u = simd::select(u > 0.0f, u, V(0.0f));
  u = simd::select(u < n, u, n);
  v = simd::select(v > 0.0f, v, V(0.0f));
  v = simd::select(v < n, v, n);
  V iu = march_floor<A>(u), iv = march_floor<A>(v);
  iu = simd::select(iu < last, iu, last);
  iv = simd::select(iv < last, iv, last);
  GridTap<A> t;
  t.node = march_index<A>(node_base + iv * c.stride_f + iu);
  t.fu = u - iu;
  t.fv = v - iv;
  t.iu = iu;
  t.iv = iv;
  return t;
}

template <class A>
inline simd::vfloat<A> bilinear(const float* field, std::size_t stride, const GridTap<A>& t) {
  using V = simd::vfloat<A>;
  const V h00 = march_gather<A>(field, t.node), h10 = march_gather<A>(field + 1, t.node);
  const V h01 = march_gather<A>(field + stride, t.node), h11 = march_gather<A>(field + stride + 1, t.node);
  const V a = h00 + t.fu * (h10 - h00), b = h01 + t.fu * (h11 - h01);
  return a + t.fv * (b - a);
}

/// The level choice at a point: level l for reach_{l-1} < r <= reach_l, r the Chebyshev distance to
/// the centre; beyond the last reach, the far plane. Selected lane-wise by a chain of compares.
template <class A>
struct Located {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  V r;            ///< Chebyshev distance to the centre
  V w;            ///< blend weight toward the next level, 0 outside the band
  M far;          ///< beyond the last level
  M next_far;     ///< the blend partner is the far plane (on the last level)
  V ox, oy, inv_cell, tile_size, reach, node_base, tile_base;  ///< the level's parameters
  V nox, noy, ninv_cell, nnode_base;                           ///< the next level's
  GridTap<A> tap;
};

template <class A>
inline Located<A> locate(const MarchContext& c, simd::vfloat<A> px, simd::vfloat<A> py) {
  using V = simd::vfloat<A>;
  Located<A> s;
  s.r = vmax<A>(simd::abs(px - c.centre_x), simd::abs(py - c.centre_y));
  const MarchLevel* lv = c.level;
  s.ox = V(lv[0].origin_x);
  s.oy = V(lv[0].origin_y);
  s.inv_cell = V(lv[0].inv_cell);
  s.tile_size = V(lv[0].tile_size);
  s.reach = V(lv[0].reach);
  V band_start(lv[0].band_start), inv_band(lv[0].inv_band);
  s.node_base = V(lv[0].node_base);
  s.tile_base = V(lv[0].tile_base);
  s.nox = V(lv[1].origin_x);
  s.noy = V(lv[1].origin_y);
  s.ninv_cell = V(lv[1].inv_cell);
  s.nnode_base = V(lv[1].node_base);
  s.next_far = simd::vmask<A>(c.levels == 1);
  for (std::uint32_t k = 0; k + 1 < c.levels; ++k) {
    // reach grows with k: once a lane is inside reach_k it stays on level k.
    const auto out = s.r > lv[k].reach;
    const MarchLevel& a = lv[k + 1];
    const MarchLevel& b = lv[k + 2];
    s.ox = simd::select(out, V(a.origin_x), s.ox);
    s.oy = simd::select(out, V(a.origin_y), s.oy);
    s.inv_cell = simd::select(out, V(a.inv_cell), s.inv_cell);
    s.tile_size = simd::select(out, V(a.tile_size), s.tile_size);
    s.reach = simd::select(out, V(a.reach), s.reach);
    band_start = simd::select(out, V(a.band_start), band_start);
    inv_band = simd::select(out, V(a.inv_band), inv_band);
    s.node_base = simd::select(out, V(a.node_base), s.node_base);
    s.tile_base = simd::select(out, V(a.tile_base), s.tile_base);
    s.nox = simd::select(out, V(b.origin_x), s.nox);
    s.noy = simd::select(out, V(b.origin_y), s.noy);
    s.ninv_cell = simd::select(out, V(b.inv_cell), s.ninv_cell);
    s.nnode_base = simd::select(out, V(b.node_base), s.nnode_base);
    if (k + 2 == c.levels) s.next_far = out;
  }
  s.far = s.r > lv[c.levels - 1].reach;
  V x = (s.r - band_start) * inv_band;
  x = simd::select(x > 0.0f, x, V(0.0f));
  x = simd::select(x < 1.0f, x, V(1.0f));
  s.w = x * x * (3.0f - 2.0f * x);
  s.w = simd::select(s.far, V(0.0f), s.w);
  s.tap = grid_tap<A>(c, px, py, s.ox, s.oy, s.inv_cell, s.node_base);
  return s;
}

/// A field (height, grad_x or grad_y) of the LOD-blended grid at a located point; `far_value` beyond.
template <class A>
inline simd::vfloat<A> blended(const MarchContext& c, const float* field, const Located<A>& s,
                               simd::vmask<A> active, simd::vfloat<A> px, simd::vfloat<A> py, float far_value) {
  using V = simd::vfloat<A>;
  const V h = bilinear<A>(field, c.stride, s.tap);
  V out = h;
  const auto band = s.w > 0.0f;
  if (simd::any(band & active)) {
    const GridTap<A> nt = grid_tap<A>(c, px, py, s.nox, s.noy, s.ninv_cell, s.nnode_base);
    const V partner = simd::select(s.next_far, V(far_value), bilinear<A>(field, c.stride, nt));
    out = simd::select(band, h + s.w * (partner - h), h);
  }
  return simd::select(s.far, V(far_value), out);
}

/// Bounds valid from the point along the ray up to s_box (m along the ray).
template <class A>
struct StepBounds {
  simd::vfloat<A> h_min, h_max, slope_x, slope_y, s_box;
};

template <class A>
inline StepBounds<A> step_bounds(const MarchContext& c, const Located<A>& s, simd::vfloat<A> px, simd::vfloat<A> py,
                                 simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> inv_dx,
                                 simd::vfloat<A> inv_dy) {
  using V = simd::vfloat<A>;
  const V big(1e30f);
  const V ti = march_floor<A>(s.tap.iu * c.inv_tile_cells), tj = march_floor<A>(s.tap.iv * c.inv_tile_cells);
  const MarchIndex<A> k = march_index<A>(s.tile_base + tj * c.tiles_per_side + ti);
  StepBounds<A> b;
  b.h_min = march_gather<A>(c.tile_min, k);
  b.h_max = march_gather<A>(c.tile_max, k);
  b.slope_x = march_gather<A>(c.tile_slope_x, k);
  b.slope_y = march_gather<A>(c.tile_slope_y, k);
  // The tile, clipped to the level's reach (beyond it a coarser level's bounds apply).
  const V x0 = s.ox + ti * s.tile_size, y0 = s.oy + tj * s.tile_size;
  const V x_lo = vmax<A>(x0, c.centre_x - s.reach), x_hi = vmin<A>(x0 + s.tile_size, c.centre_x + s.reach);
  const V y_lo = vmax<A>(y0, c.centre_y - s.reach), y_hi = vmin<A>(y0 + s.tile_size, c.centre_y + s.reach);
  const V sx = simd::select(dx > 0.0f, (x_hi - px) * inv_dx, simd::select(dx < 0.0f, (x_lo - px) * inv_dx, big));
  const V sy = simd::select(dy > 0.0f, (y_hi - py) * inv_dy, simd::select(dy < 0.0f, (y_lo - py) * inv_dy, big));
  b.s_box = vmin<A>(sx, sy);
  if (simd::any(s.far)) {
    // Beyond the last level: the flat far plane if the ray moves away from the grids for good (it is
    // outside the last reach on an axis along which it does not come back), else the global bounds.
    const V R(c.level[c.levels - 1].reach);
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
inline simd::vfloat<A> noise_level(const MarchContext& c, simd::vfloat<A> ray_offset, simd::vfloat<A> cone) {
  using V = simd::vfloat<A>;
  V l = ray_offset - march_log2<A>(cone) * c.inv_log2_lacunarity;
  l = simd::select(l > 0.0f, l, V(0.0f));
  return simd::select(l < c.max_level, l, V(c.max_level));
}

template <class A>
inline void noise_bounds(const MarchContext& c, simd::vfloat<A> level, simd::vfloat<A>& height, simd::vfloat<A>& slope) {
  using V = simd::vfloat<A>;
  height = V(0.0f);
  slope = V(0.0f);
  for (std::uint32_t i = 0; i < c.octaves; ++i) {
    // Octave i has weight W_i(level) <= 1, and 0 unless level > i.
    const auto on = level > static_cast<float>(i);
    height = height + simd::select(on, V(c.octave_height[i]), V(0.0f));
    slope = slope + simd::select(on, V(c.octave_slope[i]), V(0.0f));
  }
}

/// The two uses of capillary_impl.hpp (the only coupling to it): height alone while marching, height
/// and gradient at the hit.
template <class A>
inline simd::vfloat<A> noise_height(const CapillaryFrame& f, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> level) {
  return capillary_point<A, false>(f, x, y, level).height;
}
template <class A>
inline CapillaryPoint<A> noise_point(const CapillaryFrame& f, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> level) {
  return capillary_point<A, true>(f, x, y, level);
}

/// Per-ray constants.
template <class A>
struct MarchRay {
  using V = simd::vfloat<A>;
  V ox, oy, oz, dx, dy, dz, adx, ady, adz, inv_dx, inv_dy, level_offset;
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
  r.level_offset = zero;
  if (c.noise != nullptr) {
    const V sin_grazing = simd::select(r.adz > 1e-3f, r.adz, V(1e-3f));
    r.level_offset = c.level_offset + march_log2<A>(sin_grazing) * c.inv_log2_lacunarity;
  }
  return r;
}

/// The full (noise included) f at distance t, times sigma.
template <class A>
inline simd::vfloat<A> full_g(const MarchContext& c, const MarchRay<A>& r, simd::vfloat<A> t, simd::vfloat<A> sigma,
                              simd::vmask<A> active) {
  using V = simd::vfloat<A>;
  const V px = r.ox + t * r.dx, py = r.oy + t * r.dy, pz = r.oz + t * r.dz;
  const Located<A> s = locate<A>(c, px, py);
  V f = pz - blended<A>(c, c.height, s, active, px, py, c.far_height);
  if (c.noise != nullptr) {
    const V level = noise_level<A>(c, r.level_offset, c.cone_width + t * c.pixel_angle);
    f = f - noise_height<A>(*c.noise, px, py, level);
  }
  return sigma * f;
}

template <class A>
struct MarchResult {
  using V = simd::vfloat<A>;
  V t, x, y, z, grad_x, grad_y, level, status, evaluations;
};

template <class A>
inline MarchResult<A> march_packet(const MarchContext& c, simd::vfloat<A> ox, simd::vfloat<A> oy, simd::vfloat<A> oz,
                                   simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> dz, simd::vfloat<A> t_max) {
  using V = simd::vfloat<A>;
  using M = simd::vmask<A>;
  const V zero(0.0f), one(1.0f), big(1e30f);
  const bool noise = c.noise != nullptr;

  M finite(false);
  const MarchRay<A> r = make_march_ray<A>(c, ox, oy, oz, dx, dy, dz, finite);
  const V inv_dz = simd::div(one, simd::select(r.dz == zero, one, r.dz));

  // The ray's end and its interval in the slab.
  V t_end = simd::select(t_max < c.max_distance, t_max, V(c.max_distance));  // NaN: max_distance
  t_end = simd::select(t_end > zero, t_end, zero);
  const V t_top = (c.z_hi - r.oz) * inv_dz, t_bottom = (c.z_lo - r.oz) * inv_dz;
  const M inside = (r.oz >= c.z_lo) & (r.oz <= c.z_hi);
  const V t_enter = simd::select(r.dz > zero, t_bottom, simd::select(r.dz < zero, t_top, simd::select(inside, zero, big)));
  const V t_exit = simd::select(r.dz > zero, t_top, simd::select(r.dz < zero, t_bottom, simd::select(inside, big, zero)));
  const V t_in = vmax<A>(t_enter, zero), t_out = vmin<A>(t_exit, t_end);
  M active = finite & (t_in < t_out);

  V t = simd::select(active, t_in, zero);
  V sigma = one, t_prev = t, g_prev = zero, a = zero, ga = zero, b = zero, gb = zero, evaluations = zero;
  M crossed(false);
  for (std::int32_t it = 0; it < c.max_steps && simd::any(active); ++it) {
    const V px = r.ox + t * r.dx, py = r.oy + t * r.dy, pz = r.oz + t * r.dz;
    const Located<A> s = locate<A>(c, px, py);
    const V f_grid = pz - blended<A>(c, c.height, s, active, px, py, c.far_height);
    const V cone = c.cone_width + t * c.pixel_angle;
    // g: sigma f when it is known; outside the noise envelope a bound with the right sign.
    V g, g_env, noise_h = zero, noise_s = zero, level_term = zero;
    M near(true);
    if (noise) {
      const V level = noise_level<A>(c, r.level_offset, cone);
      noise_bounds<A>(c, level, noise_h, noise_s);
      near = simd::abs(f_grid) <= noise_h;
      V f = f_grid;
      if (simd::any(active & near)) f = simd::select(near, f_grid - noise_height<A>(*c.noise, px, py, level), f_grid);
      if (it == 0) sigma = simd::select(f >= zero, one, V(-1.0f));
      g_env = sigma * f_grid - noise_h;
      g = simd::select(near, sigma * f, g_env);
      // The level falls along the ray; its change moves the noise by at most this much per m.
      level_term = simd::div(V(c.level_rate * c.pixel_angle), vmax<A>(cone, V(1e-20f)));
    } else {
      if (it == 0) sigma = simd::select(f_grid >= zero, one, V(-1.0f));
      g = sigma * f_grid;
      g_env = g;
    }
    evaluations = evaluations + simd::select(active, one, zero);

    const M cross_now = active & (g <= zero);
    a = simd::select(cross_now, t_prev, a);
    ga = simd::select(cross_now, g_prev, ga);
    b = simd::select(cross_now, t, b);
    gb = simd::select(cross_now, g, gb);
    crossed = crossed | cross_now;
    active = active & !cross_now;
    active = active & (t < t_out);  // the sample at t_out was the last
    if (!simd::any(active)) break;

    // The step: the largest distance that provably holds no crossing, within the bounds' box, but at
    // least delta.
    const StepBounds<A> bd = step_bounds<A>(c, s, px, py, r.dx, r.dy, r.inv_dx, r.inv_dy);
    const V lip = vmax<A>(r.adz + bd.slope_x * r.adx + bd.slope_y * r.ady, V(1e-30f));
    V safe = simd::select(g_env > zero, simd::div(g_env, lip), zero);
    if (noise) {
      const V lip_full = lip + noise_s * (r.adx + r.ady) + level_term;
      safe = vmax<A>(safe, simd::select(near & (g > zero), simd::div(g, lip_full), zero));
    }
    const V top = simd::select(sigma > zero, bd.h_max + noise_h, bd.h_min - noise_h);
    const V gap = sigma * (pz - top), rate = zero - sigma * r.dz;
    safe = vmax<A>(safe, simd::select(gap > zero, simd::select(rate > zero, simd::div(gap, rate), big), zero));
    const V delta = vmax<A>(c.step_fraction * cone, V(c.min_step));
    const V step = vmax<A>(vmin<A>(safe, bd.s_box + 0.125f * delta), delta);
    t_prev = simd::select(active, t, t_prev);
    g_prev = simd::select(active, g, g_prev);
    t = simd::select(active, vmin<A>(t + step, t_out), t);
  }
  const M exhausted = active;

  // Illinois on [a, b]: g(a) > 0 >= g(b) (a == b when the ray starts on the surface).
  V t_hit = b;
  if (simd::any(crossed)) {
    V side = zero;  // +1: b was replaced last, -1: a was
    for (std::int32_t k = 0; k < c.refine_iterations; ++k) {
      const V den = ga - gb;
      V m = simd::select(den > zero, a + (b - a) * simd::div(ga, simd::select(den > zero, den, one)), a);
      m = vmax<A>(vmin<A>(m, b), a);
      const V gm = full_g<A>(c, r, m, sigma, crossed);
      const M rb = crossed & (gm <= zero), ra = crossed & !(gm <= zero);
      ga = simd::select(rb & (side > zero), ga * 0.5f, ga);  // b kept twice: halve the stale end's value
      gb = simd::select(ra & (side < zero), gb * 0.5f, gb);
      b = simd::select(rb, m, b);
      gb = simd::select(rb, gm, gb);
      a = simd::select(ra, m, a);
      ga = simd::select(ra, gm, ga);
      side = simd::select(rb, one, simd::select(ra, V(-1.0f), side));
      evaluations = evaluations + simd::select(crossed, one, zero);
    }
    const V den = ga - gb;
    t_hit = simd::select(den > zero, a + (b - a) * simd::div(ga, simd::select(den > zero, den, one)), a);
    t_hit = vmax<A>(vmin<A>(t_hit, b), a);
  }

  MarchResult<A> out;
  out.t = simd::select(crossed, t_hit, simd::select(exhausted, t, t_end));
  out.x = r.ox + out.t * r.dx;
  out.y = r.oy + out.t * r.dy;
  out.z = r.oz + out.t * r.dz;
  out.grad_x = zero;
  out.grad_y = zero;
  out.level = zero;
  if (simd::any(crossed)) {
    // The eq. 8 normal: gradients add. Grid gradients are interpolated and blended like the heights.
    const Located<A> s = locate<A>(c, out.x, out.y);
    V gx = blended<A>(c, c.grad_x, s, crossed, out.x, out.y, 0.0f);
    V gy = blended<A>(c, c.grad_y, s, crossed, out.x, out.y, 0.0f);
    if (noise) {
      const V level = noise_level<A>(c, r.level_offset, c.cone_width + out.t * c.pixel_angle);
      const CapillaryPoint<A> n = noise_point<A>(*c.noise, out.x, out.y, level);
      gx = gx + n.grad_x;
      gy = gy + n.grad_y;
      out.level = simd::select(crossed, level, zero);
    }
    out.grad_x = simd::select(crossed, gx, zero);
    out.grad_y = simd::select(crossed, gy, zero);
    evaluations = evaluations + simd::select(crossed, one, zero);
  }
  out.status = simd::select(crossed, simd::select(sigma > zero, one, V(2.0f)), simd::select(exhausted, V(3.0f), zero));
  out.evaluations = evaluations;
  return out;
}

/// n rays in packets of the ISA's width; the tail goes through the same code on a padded copy.
template <class A>
void march_rays(const MarchContext& c, const MarchRays& rays, std::size_t n, const MarchHits& hits) noexcept {
  using V = simd::vfloat<A>;
  constexpr std::size_t W = simd::width<A>;
  alignas(64) float in[7][W];
  alignas(64) float res[9][W];
  for (std::size_t i = 0; i < n; i += W) {
    const std::size_t lanes = std::min(W, n - i);
    const float* src[7] = {rays.ox + i, rays.oy + i, rays.oz + i, rays.dx + i, rays.dy + i, rays.dz + i,
                           rays.t_max != nullptr ? rays.t_max + i : nullptr};
    for (std::size_t l = 0; l < lanes; ++l) {
      for (int k = 0; k < 6; ++k) in[k][l] = src[k][l];
      in[6][l] = src[6] != nullptr ? src[6][l] : c.max_distance;
    }
    // Padding lanes: a ray going up from above the slab, done before the first sample.
    for (std::size_t l = lanes; l < W; ++l) {
      in[0][l] = c.centre_x;
      in[1][l] = c.centre_y;
      in[2][l] = c.z_hi + 1.0f;
      in[3][l] = 0.0f;
      in[4][l] = 0.0f;
      in[5][l] = 1.0f;
      in[6][l] = 0.0f;
    }
    const MarchResult<A> m = march_packet<A>(c, simd::load<A>(in[0]), simd::load<A>(in[1]), simd::load<A>(in[2]),
                                             simd::load<A>(in[3]), simd::load<A>(in[4]), simd::load<A>(in[5]),
                                             simd::load<A>(in[6]));
    const V* fields[9] = {&m.t, &m.x, &m.y, &m.z, &m.grad_x, &m.grad_y, &m.level, &m.status, &m.evaluations};
    for (int k = 0; k < 9; ++k) simd::store<A>(res[k], *fields[k]);
    for (std::size_t l = 0; l < lanes; ++l) {
      if (hits.t != nullptr) hits.t[i + l] = res[0][l];
      if (hits.x != nullptr) hits.x[i + l] = res[1][l];
      if (hits.y != nullptr) hits.y[i + l] = res[2][l];
      if (hits.z != nullptr) hits.z[i + l] = res[3][l];
      if (hits.grad_x != nullptr) hits.grad_x[i + l] = res[4][l];
      if (hits.grad_y != nullptr) hits.grad_y[i + l] = res[5][l];
      if (hits.noise_level != nullptr) hits.noise_level[i + l] = res[6][l];
      if (hits.status != nullptr) hits.status[i + l] = static_cast<MarchStatus>(static_cast<std::uint8_t>(res[7][l]));
      if (hits.evaluations != nullptr) hits.evaluations[i + l] = static_cast<std::uint32_t>(res[8][l]);
    }
  }
}

}  // namespace houle::detail
