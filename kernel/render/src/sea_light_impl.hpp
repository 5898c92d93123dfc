// The light of a sea hit seen from above and its glint (sea_light.hpp), written once for every width
// (included by render_isa.cpp and sea_light.cpp). Only +, -, *, comparisons and, in the glint,
// simd::div, simd::sqrt and simd::exp, each written in the order of the scalar expression it stands
// for: every SIMD path gives the scalar path's bits (tests/kernel/test_sea_light.cpp).
#pragma once
#include <cstddef>

#include "glint_impl.hpp"
#include "houle/render/optics.hpp"
#include "houle/render/sky.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "sea_light.hpp"

namespace houle::detail {

/// One packet's inputs (SeaLightInput), read with `load(const float*)`.
template <class A>
struct SeaLightLanes {
  using V = simd::vfloat<A>;
  V kr, lit, nx, ny, nz, dx, dy, dz, rough, cover;
  Rgb<A> reflected, under;
};

template <class A, class Load>
inline SeaLightLanes<A> sea_light_lanes(const SeaLightParams& p, const SeaLightInput& in, Load load) {
  using V = simd::vfloat<A>;
  SeaLightLanes<A> l;
  l.kr = load(in.kr);
  l.lit = load(in.lit);
  l.nx = load(in.nx), l.ny = load(in.ny), l.nz = load(in.nz);
  l.dx = load(in.dx), l.dy = load(in.dy), l.dz = load(in.dz);
  l.rough = load(in.rough);
  l.cover = in.foam != nullptr ? load(in.foam) : V(0.0f);
  // Where the ray into the air meets nothing, the sky: its radiance scaled to the renderer's units.
  const auto air = load(in.air_hit) > V(0.0f);
  l.reflected = {simd::select(air, load(in.reflected_r), load(in.sky_r) * V(p.sky_scale[0])),
                 simd::select(air, load(in.reflected_g), load(in.sky_g) * V(p.sky_scale[1])),
                 simd::select(air, load(in.reflected_b), load(in.sky_b) * V(p.sky_scale[2]))};
  l.under = {load(in.under_r), load(in.under_g), load(in.under_b)};
  return l;
}

/// Whether the glint lobe of slope variance `variance` may reach the camera: the lobe is skipped
/// where it is below e^-30 of its peak (tan^2 / 2 sigma^2 > 30). With the half vector h = v + sun
/// unnormalised, cos^2 = (n.h)^2 / h.h: the test multiplied through by h.h needs no square root.
template <class A>
inline simd::vmask<A> glint_lobe(const SeaLightParams& p, const SeaLightLanes<A>& l, simd::vfloat<A> variance) {
  using V = simd::vfloat<A>;
  const V hx = -l.dx + V(p.sun[0]), hy = -l.dy + V(p.sun[1]), hz = -l.dz + V(p.sun[2]);
  const V nh = (l.nx * hx + l.ny * hy) + l.nz * hz, hh = (hx * hx + hy * hy) + hz * hz;
  return (nh > V(0.0f)) & ((hh - nh * nh) < ((V(60.0f) * (variance + V(sun_disc_slope_variance))) * nh) * nh);
}

/// The light: the rays' radiance split by the Fresnel reflectance, the glint added, then the foam, a
/// white diffuse layer lit like an object's face along the normal, laid over it by its cover.
template <class A>
inline Rgb<A> sea_light(const SeaLightParams& p, const SeaLightLanes<A>& l, simd::vfloat<A> glint) {
  using V = simd::vfloat<A>;
  const auto seen_through = l.kr < V(1.0f);
  const V kt = V(1.0f) - l.kr;
  const auto channel = [&](V reflected, V under, int c) {
    return (reflected * l.kr + simd::select(seen_through, under, V(0.0f)) * kt) + V(p.sun_rgb[c]) * glint;
  };
  const Rgb<A> surface{channel(l.reflected.r, l.under.r, 0), channel(l.reflected.g, l.under.g, 1),
                       channel(l.reflected.b, l.under.b, 2)};
  constexpr float foam_albedo = 0.85f;
  const V cos_sun = (l.nx * V(p.sun[0]) + l.ny * V(p.sun[1])) + l.nz * V(p.sun[2]);
  const auto sunny = (l.lit > V(0.0f)) & (cos_sun > V(0.0f));
  const V facing = V(0.5f) * (V(1.0f) + l.nz);
  const auto foam = [&](V surface_c, int c) {
    const V f = ((V(p.ambient[c]) * facing) + simd::select(sunny, V(p.sun_rgb[c]) * cos_sun, V(0.0f))) * V(foam_albedo);
    return simd::select(l.cover > V(0.0f), surface_c * (V(1.0f) - l.cover) + f * l.cover, surface_c);
  };
  return {foam(surface.r, 0), foam(surface.g, 1), foam(surface.b, 2)};
}

template <class A>
void sea_light_batch(const SeaLightParams& p, const SeaLightInput& in, std::size_t n, SeaLightOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const auto above = b.load(in.side) > V(0.0f);
    if (!simd::any(above)) {
      b.store(out.glint_lobe, V(0.0f));
      return;
    }
    const SeaLightLanes<A> l = sea_light_lanes<A>(p, in, [&](const float* a) { return b.load(a); });
    const Rgb<A> c = sea_light<A>(p, l, V(0.0f));
    b.store(out.r, c.r);
    b.store(out.g, c.g);
    b.store(out.b, c.b);
    const auto lobe = above & (l.lit > V(0.0f)) & glint_lobe<A>(p, l, V(p.dropped_max) + l.rough);
    b.store(out.glint_lobe, simd::select(lobe, V(1.0f), V(0.0f)));
  });
}

template <class A>
void sea_glint_batch(const SeaLightParams& p, const SeaLightInput& in, const float* glint_variance, std::size_t n,
                     SeaLightOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const auto lobe = b.load(out.glint_lobe) > V(0.0f);
    if (!simd::any(lobe)) return;
    const SeaLightLanes<A> l = sea_light_lanes<A>(p, in, [&](const float* a) { return b.load(a); });
    const V normal[3] = {l.nx, l.ny, l.nz}, view[3] = {-l.dx, -l.dy, -l.dz};
    const V glint = V(std::numbers::pi_v<float>) *
                    sun_glint<A>(normal, view, p.sun, b.load(glint_variance), 1.0f, water_refractive_index);
    const Rgb<A> c = sea_light<A>(p, l, glint);
    b.store(out.r, simd::select(lobe, c.r, b.load(out.r)));
    b.store(out.g, simd::select(lobe, c.g, b.load(out.g)));
    b.store(out.b, simd::select(lobe, c.b, b.load(out.b)));
  });
}

}  // namespace houle::detail
