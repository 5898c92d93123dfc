// The light under the sea (under_light.hpp), written once for every width (included by render_isa.cpp).
// The same operations in the same order as the renderer's scalar lit_in_water and sunlit, which keep
// the lanes asked about: only +, -, *, simd::div, comparisons, exact conversions and the masks'
// gathers, so every SIMD path gives the scalar path's bits (tests/kernel/test_under_light.cpp).
#pragma once
#include <cstddef>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "shadow_mask.hpp"
#include "under_light.hpp"

namespace houle::detail {

template <class A>
void under_light_batch(const UnderLightParams& p, const UnderLightInput& in, std::size_t n, UnderLightOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const V zero(0.0f), one(1.0f);
    const auto sea = b.load(in.side) > zero;
    const auto met = sea & (b.load(in.met) > zero);
    V ask = zero;
    // Whether the sun reaches the sea hit: clear unless its line along the sun may meet a caster.
    if (p.shadows && p.sun[2] > 0.0f && simd::any(sea)) {
      const V x = b.load(in.x), y = b.load(in.y), z = b.load(in.z), offset = V(1e-3f) + V(1e-4f) * b.load(in.t);
      const auto below = sea & (V(p.casters_top) > z);
      if (simd::any(below)) {
        const auto may = shadow_may_meet<A>(p.sun_mask, x + offset * b.load(in.nx), y + offset * b.load(in.ny),
                                            z + offset * b.load(in.nz));
        ask = simd::select(below & may, one, zero);
      }
    }
    b.store(out.lit, simd::select(sea, one, zero));
    if (!simd::any(met)) {
      b.store(out.ask, ask);
      for (float* o : {out.r, out.g, out.b, out.path}) b.store(o, zero);
      return;
    }
    // The surface met, at q, its normal turned to the side the ray sees.
    const V t = b.load(in.hit_t), dx = b.load(in.dx), dy = b.load(in.dy), dz = b.load(in.dz);
    const V qx = b.load(in.x) + t * dx, qy = b.load(in.y) + t * dy, qz = b.load(in.z) + t * dz;
    V nx = b.load(in.hit_nx), ny = b.load(in.hit_ny), nz = b.load(in.hit_nz);
    const auto away = (nx * dx + ny * dy) + nz * dz > zero;
    nx = simd::select(away, -nx, nx);
    ny = simd::select(away, -ny, ny);
    nz = simd::select(away, -nz, nz);
    const V tilt = V(0.5f) * (one + nz);
    const V cos_sun = (nx * V(p.sun_water[0]) + ny * V(p.sun_water[1])) + nz * V(p.sun_water[2]);
    auto facing = met & (cos_sun > zero);
    if (!(p.sun_water[2] > 0.0f)) facing = decltype(facing)(false);
    const V depth = max_as_std(zero, -qz);
    if (p.shadows && simd::any(facing)) {
      // Along the refracted sun up to the still sea level, then along the sun in air (lit_in_water).
      const V offset = V(1e-3f) + V(1e-4f) * t;
      const auto water_may = shadow_may_meet<A>(p.sun_water_mask, qx + offset * nx, qy + offset * ny, qz + offset * nz);
      const V rise = simd::div(depth, V(p.sun_water[2]));
      const V sx = qx + rise * V(p.sun_water[0]), sy = qy + rise * V(p.sun_water[1]), sz = qz + rise * V(p.sun_water[2]);
      auto air_may = V(p.casters_top) > sz;
      if (!(p.sun[2] > 0.0f)) air_may = decltype(air_may)(false);
      if (simd::any(facing & air_may)) {
        air_may = air_may & shadow_may_meet<A>(p.sun_mask, sx + offset * V(p.sun[0]), sy + offset * V(p.sun[1]),
                                               sz + offset * V(p.sun[2]));
      }
      ask = ask + simd::select(facing & (water_may | air_may), V(2.0f), zero);
    }
    b.store(out.ask, ask);
    // Lit wherever it faces the sun; where asked, the renderer's own answer replaces these.
    const V r = simd::select(facing, V(p.ambient[0]) * tilt + V(p.sun_rgb[0]) * cos_sun, V(p.ambient[0]) * tilt);
    const V g = simd::select(facing, V(p.ambient[1]) * tilt + V(p.sun_rgb[1]) * cos_sun, V(p.ambient[1]) * tilt);
    const V bl = simd::select(facing, V(p.ambient[2]) * tilt + V(p.sun_rgb[2]) * cos_sun, V(p.ambient[2]) * tilt);
    b.store(out.r, simd::select(met, b.load(in.albedo_r) * r, zero));
    b.store(out.g, simd::select(met, b.load(in.albedo_g) * g, zero));
    b.store(out.b, simd::select(met, b.load(in.albedo_b) * bl, zero));
    const V path = p.sun_water[2] > 0.0f ? simd::div(depth, V(p.sun_water[2])) : zero;
    b.store(out.path, simd::select(met, path, zero));
  });
}

}  // namespace houle::detail
