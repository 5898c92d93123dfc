// The water colour table's per-pixel lookups (WaterColourLut, colour.hpp: eq. 12 per wavelength through
// Smits' basis) and the gamut mapping to grey, written once for every width: colour.cpp's scalar
// functions are their scalar instances, the shading calls them a row at a time (included by colour.cpp
// and render_isa.cpp). Only +, -, *, simd::div, comparisons, exact conversions and gathers: every SIMD
// path gives the scalar path's bits (tests/kernel/test_colour.cpp).
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/render/colour.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"

namespace houle::detail {

/// CIE Y of linear sRGB: the middle row of docs/rendering.md 4.2's inverse matrix.
inline constexpr double luminance_row[3] = {0.2126390, 0.7151687, 0.0721923};

template <class A>
inline simd::vfloat<A> luminance_of(const Rgb<A>& c) {
  using V = simd::vfloat<A>;
  return V(float(luminance_row[0])) * c.r + V(float(luminance_row[1])) * c.g + V(float(luminance_row[2])) * c.b;
}

/// Mix c + t (Y - c) with t = -lo / (Y - lo) when the smallest channel lo is negative; t = 0 (c
/// unchanged) when it is not; t = 1 (black) when Y <= 0. Without branches: whether the sum of the
/// water terms leaves the gamut changes from pixel to pixel.
template <class A>
inline Rgb<A> grey_mapped(const Rgb<A>& c) {
  using V = simd::vfloat<A>;
  const V lo = min_as_std(min_as_std(c.r, c.g), c.b);
  const V y = luminance_of<A>(c);
  const V neg = max_as_std(-lo, V(0.0f));
  const V t = min_as_std(simd::div(neg, max_as_std(y + neg, V(1e-30f))), V(1.0f));
  const V grey = max_as_std(y, V(0.0f));
  // The smallest channel comes out 0 up to rounding; never let it be negative.
  return {max_as_std(c.r + t * (grey - c.r), V(0.0f)), max_as_std(c.g + t * (grey - c.g), V(0.0f)),
          max_as_std(c.b + t * (grey - c.b), V(0.0f))};
}

/// The water colour table as the lookups read it: `entries` rows of water_row_floats, row k at path
/// length d = half_distance k / (entries - 1 - k) (the last at infinity), stored as pairs: value q of
/// row k and of row k + 1 at pairs[2 (k water_row_floats + q) + 0, 1], for k < entries - 1, so that a
/// lookup fetches both rows' values as one 64-bit element (half the gathered elements, docs/design.md 10).
inline constexpr int water_bases = smits_basis_count;
inline constexpr int water_row_floats = (water_bases + 1) * 3;  // 7 bases and I_sea, RGB each
struct WaterTable {
  const float* pairs;
  int entries;
  float half_distance_m;
};

/// Where distance d falls in the table: the first pair of the row below and the weight of the one
/// above. u = d / (d + d_half), written so that d = +infinity gives 1 and NaN or d < 0 give 0.
template <class A>
struct WaterPosition {
  simd::vint<A> row;
  simd::vfloat<A> t;
};
template <class A>
inline WaterPosition<A> water_position(const WaterTable& w, simd::vfloat<A> distance_m) {
  using V = simd::vfloat<A>;
  using I = simd::vint<A>;
  const V d = simd::max_as_std(V(0.0f), distance_m);
  const V u = V(1.0f) - simd::div(V(w.half_distance_m), d + V(w.half_distance_m));
  const V x = u * V(float(w.entries - 1));
  using std::min;  // int32 in the scalar path, xsimd's by argument-dependent lookup for batches
  const I i = min(simd::to_int_exact(x), I(w.entries - 2));
  return {i * I(water_row_floats), x - simd::to_float_exact(i)};
}

/// Column `column` (a basis, or water_bases for I_sea) of the table at p, interpolated.
template <class A>
inline Rgb<A> water_lerp(const WaterTable& w, const WaterPosition<A>& p, simd::vint<A> column) {
  using I = simd::vint<A>;
  const I a = p.row + column * I(3);
  const auto channel = [&](int c) {
    simd::vfloat<A> lo, hi;
    simd::gather_pair(w.pairs, a + I(c), lo, hi);
    return lo + p.t * (hi - lo);
  };
  return {channel(0), channel(1), channel(2)};
}

/// Smits' weights with the basis as a table column (white 0, cyan..yellow 1-3, red..blue 4-6).
template <class A>
struct SmitsLanes {
  simd::vfloat<A> white, secondary, primary;
  simd::vint<A> secondary_column, primary_column;
};

/// Smits 1999 (docs/rendering.md 4.1) in sorted form: the smallest channel is white; the middle one's
/// excess over it goes to the secondary lacking the smallest channel (cyan lacks red, ...), the largest
/// one's excess over the middle to its primary; ties: the smallest to the first channel, the largest
/// to the last. Negative channels count as 0. Written without data-dependent branches: colours along a
/// row of pixels change order unpredictably.
template <class A>
inline SmitsLanes<A> smits_lanes(const Rgb<A>& c) {
  using V = simd::vfloat<A>;
  const V r = max_as_std(c.r, V(0.0f)), g = max_as_std(c.g, V(0.0f)), b = max_as_std(c.b, V(0.0f));
  const V lo = min_as_std(min_as_std(r, g), b), hi = max_as_std(max_as_std(r, g), b);
  const V mid = max_as_std(min_as_std(r, g), min_as_std(max_as_std(r, g), b));  // exact median
  const V arg_lo = simd::select((r <= g) & (r <= b), V(0.0f), simd::select(g <= b, V(1.0f), V(2.0f)));
  const V arg_hi = simd::select((b >= r) & (b >= g), V(2.0f), simd::select(g >= r, V(1.0f), V(0.0f)));
  return {lo, mid - lo, hi - mid, simd::to_int_exact(V(1.0f) + arg_lo), simd::to_int_exact(V(4.0f) + arg_hi)};
}

/// K I_obj at p (WaterColourLut::absorbed): the object's Smits weights times their bases' rows.
template <class A>
inline Rgb<A> water_absorbed(const WaterTable& w, const WaterPosition<A>& p, const Rgb<A>& object) {
  const SmitsLanes<A> s = smits_lanes<A>(object);
  const Rgb<A> lw = water_lerp<A>(w, p, simd::vint<A>(0));
  const Rgb<A> ls = water_lerp<A>(w, p, s.secondary_column);
  const Rgb<A> lp = water_lerp<A>(w, p, s.primary_column);
  return {s.white * lw.r + s.secondary * ls.r + s.primary * lp.r, s.white * lw.g + s.secondary * ls.g + s.primary * lp.g,
          s.white * lw.b + s.secondary * ls.b + s.primary * lp.b};
}

/// (1 - K) I_sea at distance d (WaterColourLut::sea_part).
template <class A>
inline Rgb<A> water_sea_part(const WaterTable& w, const WaterPosition<A>& p) {
  return water_lerp<A>(w, p, simd::vint<A>(water_bases));
}

/// docs/rendering.md 3.4 with its refinement: K(d + s) I_obj + (1 - K(d)) I_sea illumination for an
/// object seen through d m of water and lit through s m of it, gamut-mapped.
template <class A>
inline Rgb<A> water_mix(const WaterTable& w, const Rgb<A>& object, simd::vfloat<A> distance_m, simd::vfloat<A> light_path_m,
                        simd::vfloat<A> illumination) {
  const Rgb<A> a = water_absorbed<A>(w, water_position<A>(w, distance_m + light_path_m), object);
  const Rgb<A> sea = water_sea_part<A>(w, water_position<A>(w, distance_m));
  return grey_mapped<A>({a.r + sea.r * illumination, a.g + sea.g * illumination, a.b + sea.b * illumination});
}

template <class A>
void water_mix_batch(const WaterTable& w, const WaterMixInput& in, std::size_t n, WaterMixOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const Rgb<A> c = water_mix<A>(w, {b.load(in.r), b.load(in.g), b.load(in.b)}, b.load(in.distance_m),
                                  b.load(in.light_path_m), b.load(in.illumination));
    b.store(out.r, c.r);
    b.store(out.g, c.g);
    b.store(out.b, c.b);
  });
}

}  // namespace houle::detail
