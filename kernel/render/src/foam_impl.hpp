// Surf foam on the sea (docs/rendering.md 3.7), written once for every width: the renderer calls it a
// row of sea hits at a time (included by render_isa.cpp). Only +, -, *, simd::div, comparisons, exact
// conversions and gathers, and the lattice noise: every SIMD path gives the scalar path's bits
// (tests/kernel/test_foam.cpp).
#pragma once
#include <cstddef>
#include <limits>

#include "foam.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "lattice_noise_impl.hpp"

namespace houle::detail {

/// How much of the sea at (x, y, z) with gradient (gx, gy) foam covers, for a pixel footprint (m): where
/// the surf map says waves break, on the crests (their height against the breaking wave's amplitude)
/// and most on their front faces (the surface falling along the waves' travel), with a thinner sheet
/// of spent foam between them; patchy, the patches faded out as the footprint grows past them. Off the
/// map its nearest edge point's foam, but for a wall's toe; 0 for a NaN position.
template <class A>
inline simd::vfloat<A> foam_cover(const SurfView& m, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z,
                                  simd::vfloat<A> gx, simd::vfloat<A> gy, simd::vfloat<A> footprint) {
  using V = simd::vfloat<A>;
  using I = simd::vint<A>;
  const V u = simd::div(x - V(m.origin_x), V(m.cell)), v = simd::div(y - V(m.origin_y), V(m.cell));
  // Off the map the nearest point of its edge holds, as the sea's fields do beyond the domain
  // (docs/physics.md 2.8), but not a wall's toe: the wall may end there. NaN lanes read node 0 and are
  // dropped at the end.
  const auto inside = (u == u) & (v == v);
  const auto on_map = (u >= V(0.0f)) & (v >= V(0.0f)) & (u <= V(m.u_end)) & (v <= V(m.v_end));
  const V us = clamp_as_std(simd::select(inside, u, V(0.0f)), V(0.0f), V(m.u_end));
  const V vs = clamp_as_std(simd::select(inside, v, V(0.0f)), V(0.0f), V(m.v_end));
  const V fi = simd::min(simd::floor_exact(us), V(m.u_end - 1.0f)), fj = simd::min(simd::floor_exact(vs), V(m.v_end - 1.0f));
  const I i = simd::to_int_exact(fi), j = simd::to_int_exact(fj);
  const V a = us - fi, b = vs - fj;
  const I n00 = (j * I(m.nx) + i) * I(4), n01 = n00 + I(4 * m.nx);
  // Fields k and k + 1 (foam, dir_x, dir_y, amplitude) bilinear, each corner's two as one 64-bit
  // element (docs/design.md 10).
  const auto fields = [&](int k, V& first, V& second) {
    V f00, g00, f10, g10, f01, g01, f11, g11;
    simd::gather_adjacent(m.nodes, n00 + I(k), f00, g00);
    simd::gather_adjacent(m.nodes, n00 + I(4 + k), f10, g10);
    simd::gather_adjacent(m.nodes, n01 + I(k), f01, g01);
    simd::gather_adjacent(m.nodes, n01 + I(4 + k), f11, g11);
    const auto lerp2 = [&](V q00, V q10, V q01, V q11) {
      const V lo = q00 + a * (q10 - q00), hi = q01 + a * (q11 - q01);
      return lo + b * (hi - lo);
    };
    first = lerp2(f00, f10, f01, f11);
    second = lerp2(g00, g10, g01, g11);
  };
  V foam, dir_x;
  fields(0, foam, dir_x);
  const auto foaming = inside & (foam > V(0.0f));
  if (!simd::any(foaming)) return V(0.0f);
  V dir_y, amplitude;
  fields(2, dir_y, amplitude);
  const V up = clamp_as_std(simd::div(z, max_as_std(amplitude, V(0.05f))) + V(0.3f), V(0.0f), V(1.0f));
  const V crest = up * up * (V(3.0f) - V(2.0f) * up);
  const V moving = dir_x * dir_x + dir_y * dir_y;  // 0 at a wall's toe: every crest foams
  const auto carried = on_map | (moving > V(0.25f));
  const V front = simd::select(moving > V(0.25f),
                               clamp_as_std(V(-5.0f) * (gx * dir_x + gy * dir_y), V(0.0f), V(1.0f)), V(1.0f));
  const V patches = clamp_as_std(V(2.0f) - simd::div(footprint * V(8.0f), V(1.5f)), V(0.0f), V(1.0f));
  // Where the patches are faded out the noise is not evaluated in the scalar path: the same bits.
  const auto patchy = patches > V(0.0f);
  const V noise = simd::any(patchy) ? lattice_noise<A>(x * V(0.8f) + V(5.0f), y * V(0.8f)) : V(0.0f);
  const V texture = simd::select(patchy, V(0.7f) + V(0.3f) * patches * noise, V(0.7f));
  // Thinning foam (carried behind the break, 0 < foam < 1) breaks up into lace: a coarser noise of
  // about 3 m moves it by up to what it lacks, less where it is too thin to show at all. The noise is
  // two lattices turned 45 degrees from each other (+-22.5 from the axes), so that the lace's edges
  // favour no direction: from one lattice they ran along its axes and read from above as squares.
  // Their sum over sqrt 2 keeps one lattice's spread.
  const V lace_fade = clamp_as_std(V(2.0f) - simd::div(footprint * V(2.4f), V(1.5f)), V(0.0f), V(1.0f));
  const V thin = (V(1.0f) - foam) * min_as_std(foam * V(5.0f), V(1.0f));
  const auto lacy = (lace_fade > V(0.0f)) & (thin > V(0.0f));
  V lace_noise(0.0f);
  if (simd::any(lacy)) {
    const V c = x * V(0.3f * 0.92387953f), s = x * V(0.3f * 0.38268343f), cy = y * V(0.3f * 0.92387953f), sy = y * V(0.3f * 0.38268343f);
    lace_noise = (lattice_noise<A>(c - sy - V(11.0f), s + cy + V(7.0f)) + lattice_noise<A>(c + sy + V(5.0f), cy - s - V(13.0f))) *
                 V(0.70710678f);
  }
  const V laced = simd::select(lacy, clamp_as_std(foam + thin * lace_fade * lace_noise, V(0.0f), V(1.0f)), foam);
  const V cover = clamp_as_std(laced * (V(0.2f) + crest * (V(0.3f) + V(0.7f) * front)) * texture, V(0.0f), V(1.0f));
  return simd::select(foaming & carried, cover, V(0.0f));
}

/// foam_cover of the sea hits seen from above (side > 0) of a row, 0 elsewhere; footprint = t
/// pixel_angle.
template <class A>
void foam_cover_batch(const SurfView& m, const FoamInput& in, std::size_t n, float pixel_angle, float* cover) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const auto above = b.load(in.side) > V(0.0f);
    if (!simd::any(above)) {
      b.store(cover, V(0.0f));
      return;
    }
    // Lanes not above the sea (padding too) are moved off the map.
    const V x = simd::select(above, b.load(in.x), V(std::numeric_limits<float>::quiet_NaN()));
    const V c = foam_cover<A>(m, x, b.load(in.y), b.load(in.z), b.load(in.gx), b.load(in.gy), b.load(in.t) * V(pixel_angle));
    b.store(cover, c);
  });
}

}  // namespace houle::detail
