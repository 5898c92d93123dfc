// The light under the sea (under_light.hpp), written once for every width (included by render_isa.cpp,
// and by renderer.cpp, whose lit_in_water lights the lanes asked about with the scalar instances of
// the same pieces): only +, -, *, simd::div, comparisons, exact conversions and the masks' gathers, so
// every SIMD path gives the scalar path's bits (tests/kernel/test_under_light.cpp).
#pragma once
#include <cstddef>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "shadow_mask.hpp"
#include "under_light.hpp"

namespace houle::detail {

/// m of water the sun's light crosses down to depth -z under a flat sea (0 above it).
template <class A>
inline simd::vfloat<A> sun_path_in_water(const UnderLightParams& p, simd::vfloat<A> z) {
  using V = simd::vfloat<A>;
  const V depth = max_as_std(V(0.0f), -z);
  return p.sun_water[2] > 0.0f ? simd::div(depth, V(p.sun_water[2])) : V(0.0f);
}

/// A surface under the sea met along d, with its normal turned to the side the ray sees.
template <class A>
struct SeaBedFacet {
  simd::vfloat<A> nx, ny, nz, cos_sun;  ///< cos_sun: with the refracted sun
  simd::vmask<A> facing;                ///< the refracted sun can light it (ignoring shadows)
};
template <class A>
inline SeaBedFacet<A> sea_bed_facet(const UnderLightParams& p, simd::vfloat<A> nx, simd::vfloat<A> ny,
                                    simd::vfloat<A> nz, simd::vfloat<A> dx, simd::vfloat<A> dy, simd::vfloat<A> dz) {
  using V = simd::vfloat<A>;
  SeaBedFacet<A> f;
  const auto away = (nx * dx + ny * dy) + nz * dz > V(0.0f);
  f.nx = simd::select(away, -nx, nx);
  f.ny = simd::select(away, -ny, ny);
  f.nz = simd::select(away, -nz, nz);
  f.cos_sun = (f.nx * V(p.sun_water[0]) + f.ny * V(p.sun_water[1])) + f.nz * V(p.sun_water[2]);
  f.facing = f.cos_sun > V(0.0f);
  if (!(p.sun_water[2] > 0.0f)) f.facing = decltype(f.facing)(false);
  return f;
}

/// The light the facet of that albedo sends back: the sky's by its tilt, and the refracted sun's where
/// `sunlit` (its lanes facing the sun and in no caster's shadow).
template <class A>
inline Rgb<A> sea_bed_light(const UnderLightParams& p, const SeaBedFacet<A>& f, const Rgb<A>& albedo,
                            simd::vmask<A> sunlit) {
  using V = simd::vfloat<A>;
  const V tilt = V(0.5f) * (V(1.0f) + f.nz);
  const auto channel = [&](int c, V a) {
    const V sky = V(p.ambient[c]) * tilt;
    return a * simd::select(sunlit, sky + V(p.sun_rgb[c]) * f.cos_sun, sky);
  };
  return {channel(0, albedo.r), channel(1, albedo.g), channel(2, albedo.b)};
}

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
    const SeaBedFacet<A> f = sea_bed_facet<A>(p, b.load(in.hit_nx), b.load(in.hit_ny), b.load(in.hit_nz), dx, dy, dz);
    const auto facing = met & f.facing;
    const V path = sun_path_in_water<A>(p, qz);
    if (p.shadows && simd::any(facing)) {
      // Along the refracted sun up to the still sea level, then along the sun in air (lit_in_water).
      const V offset = V(1e-3f) + V(1e-4f) * t;
      const auto water_may =
          shadow_may_meet<A>(p.sun_water_mask, qx + offset * f.nx, qy + offset * f.ny, qz + offset * f.nz);
      const V sx = qx + path * V(p.sun_water[0]), sy = qy + path * V(p.sun_water[1]), sz = qz + path * V(p.sun_water[2]);
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
    const Rgb<A> c = sea_bed_light<A>(p, f, {b.load(in.albedo_r), b.load(in.albedo_g), b.load(in.albedo_b)}, facing);
    b.store(out.r, simd::select(met, c.r, zero));
    b.store(out.g, simd::select(met, c.g, zero));
    b.store(out.b, simd::select(met, c.b, zero));
    b.store(out.path, simd::select(met, path, zero));
  });
}

}  // namespace houle::detail
