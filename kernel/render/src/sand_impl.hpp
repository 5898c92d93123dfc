// The sand's colour (docs/rendering.md 3.6), written once for every width: the renderer's scalar paths
// call its scalar instance, a row's floor hits go through it a packet at a time (included by
// renderer.cpp and render_isa.cpp). Only +, -, *, simd::div, comparisons and the lattice noise: every
// SIMD path gives the scalar path's bits (tests/kernel/test_sand.cpp).
#pragma once
#include <cstddef>

#include "houle/render/colour.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"
#include "lattice_noise_impl.hpp"
#include "sand.hpp"

namespace houle::detail {

/// The sand at (x, y, z) for a dry reflectance `dry`: wet and darker (0.55 of the dry reflectance) under
/// the water and up to wet_top above it, drying over the next metre; a grain of +-8 % (lattices of
/// 2.3 m and 0.7 m) so a beach is not a flat plane, each lattice faded out as the pixel's footprint (m)
/// reaches a quarter of its spacing: finer it would alias into speckle.
template <class A>
inline Rgb<A> sand_at(const LinearRgb& dry, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z,
                      simd::vfloat<A> footprint) {
  using V = simd::vfloat<A>;
  constexpr float wet_top = 0.3f, drying = 1.0f, wet = 0.55f;
  const V u = clamp_as_std(simd::div(z - V(wet_top), V(drying)), V(0.0f), V(1.0f));
  const V dryness = u * u * (V(3.0f) - V(2.0f) * u);
  const V cx = clamp_as_std(x, V(-1e6f), V(1e6f)), cy = clamp_as_std(y, V(-1e6f), V(1e6f));
  const auto fade = [&](float spacing) {
    return clamp_as_std(V(2.0f) - simd::div(footprint * V(8.0f), V(spacing)), V(0.0f), V(1.0f));
  };
  // A lattice faded out adds (+-)0 whatever its noise: the noise is not evaluated there (the same bits).
  const V coarse = fade(2.3f), fine = fade(0.7f);
  const auto coarse_on = coarse > V(0.0f), fine_on = fine > V(0.0f);
  const V coarse_noise = simd::any(coarse_on) ? lattice_noise<A>(cx * V(0.43f), cy * V(0.43f)) : V(0.0f);
  const V fine_noise = simd::any(fine_on) ? lattice_noise<A>(cx * V(1.4f) + V(17.0f), cy * V(1.4f)) : V(0.0f);
  const V grain = V(1.0f) + simd::select(coarse_on, V(0.05f) * coarse * coarse_noise, V(0.0f)) +
                  simd::select(fine_on, V(0.03f) * fine * fine_noise, V(0.0f));
  const V k = (V(wet) + V(1.0f - wet) * dryness) * grain;
  return {min_as_std(V(dry.r) * k, V(1.0f)), min_as_std(V(dry.g) * k, V(1.0f)), min_as_std(V(dry.b) * k, V(1.0f))};
}

template <class A>
void sand_albedo_batch(const LinearRgb& dry, const SandInput& in, std::size_t n, SandOutput out) noexcept {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const auto on = b.load(in.on_sand) > V(0.0f);
    if (!simd::any(on)) {
      b.store(out.r, V(0.0f));
      b.store(out.g, V(0.0f));
      b.store(out.b, V(0.0f));
      return;
    }
    // Lanes off the sand (padding too) are taken at the origin, far: no noise of their own.
    const V x = simd::select(on, b.load(in.x), V(0.0f)), y = simd::select(on, b.load(in.y), V(0.0f));
    const V footprint = simd::select(on, b.load(in.footprint), V(1e6f));
    const Rgb<A> c = sand_at<A>(dry, x, y, b.load(in.z), footprint);
    b.store(out.r, simd::select(on, c.r, V(0.0f)));
    b.store(out.g, simd::select(on, c.g, V(0.0f)));
    b.store(out.b, simd::select(on, c.b, V(0.0f)));
  });
}

}  // namespace houle::detail
