// The sky table's lookup (SkyLut, sky.hpp), written once for every width: SkyLut::lookup is its scalar
// instance, the shading reads it per packet (included by sky.cpp and render_isa.cpp).
// Only +, -, *, simd::div, simd::sqrt, comparisons and exact integer conversions, so every SIMD path
// gives the scalar path's bits (tests/kernel/test_sky.cpp). Minima and maxima are lane_ops.hpp's: a NaN
// direction reads texel (0, 0) on every path.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "lane_ops.hpp"

namespace houle::detail {

/// The table's shape (SkyLut::width, SkyLut::height) and the lowest view z it holds.
inline constexpr int sky_columns = 128, sky_rows = 32;
// cos(sky_max_view_zenith_rad) = sin(0.001): the lowest view z the model is evaluated at.
inline constexpr double sky_min_view_z = 9.9999983333334168e-4;
// The row warp's k (sky_row_of_z; sky.cpp's z_of_row says why 0.35).
inline constexpr double sky_row_warp = 0.35;

// Column coordinate of a view's azimuth: the "diamond angle" p in [0, 4), a monotonic stand-in for
// atan2 made of one division and a sign. With t = x / (|x| + |y|): p = 1 - t for y >= 0 and
// 3 + t for y < 0 (p = 0 along +x, 1 along +y, 2 along -x, 3 along -y). Columns uniform in p are
// 0.64x to 1.27x the spacing of uniform azimuth, which the accuracy test covers. A polynomial atan2
// cost more, and its octant branches mispredict: reflected rays point every which way.
template <class A>
inline simd::vfloat<A> sky_column_of_xy(simd::vfloat<A> x, simd::vfloat<A> y) {
  using V = simd::vfloat<A>;
  const V t = simd::div(x, max_as_std(simd::abs(x) + simd::abs(y), V(1e-30f)));
  // copysign(1, y): the sign bit of y on 1.
  const simd::vint<A> sign = simd::bitcast_to_int(y) & simd::vint<A>(INT32_MIN);
  const V one_signed = simd::bitcast_to_float(sign | simd::bitcast_to_int(V(1.0f)));
  return V(2.0f) - one_signed * (V(1.0f) + t);
}

// Row coordinate v in [0, 1] of a view with z component `z` (see SkyLut): z' = z rescaled from
// [min_view_z, 1] to [0, 1], warped by w = z' (1 + k) / (z' + k), then v = 1 - sqrt(1 - w).
// The sqrt makes rows about uniform in zenith angle near the zenith; the warp packs them towards the
// horizon, where the Perez term 1 + A e^{B / cos(theta)} bends most.
template <class A>
inline simd::vfloat<A> sky_row_of_z(simd::vfloat<A> z) {
  using V = simd::vfloat<A>;
  constexpr float z0 = float(sky_min_view_z), scale = float(1.0 / (1.0 - sky_min_view_z)), k = float(sky_row_warp);
  const V zr = min_as_std(max_as_std((z - V(z0)) * V(scale), V(0.0f)), V(1.0f));
  const V w = simd::div(zr * V(1.0f + k), zr + V(k));
  return V(1.0f) - simd::sqrt(max_as_std(V(1.0f) - w, V(0.0f)));
}

template <class A>
struct SkyRgb {
  simd::vfloat<A> r, g, b;
};

/// Bilinear lookup in `pairs` along the unit direction (x, y, z); below the horizon gives the horizon
/// at that azimuth. The table holds, for each of sky_rows rows and sky_columns columns and each
/// channel c, the texel's value and its right neighbour's: pairs[2 ((j sky_columns + i) 3 + c) + 0, 1]
/// (the columns run on to a repeat of column 0), so a row's two texels are one 64-bit element (half
/// the gathered elements, docs/design.md 10).
template <class A>
inline SkyRgb<A> sky_lookup(const float* pairs, simd::vfloat<A> x, simd::vfloat<A> y, simd::vfloat<A> z) {
  using V = simd::vfloat<A>;
  using I = simd::vint<A>;
  const V fu = min_as_std(max_as_std(V(0.0f), sky_column_of_xy<A>(x, y) * V(float(sky_columns / 4))),
                              V(float(sky_columns)));
  const V fv = max_as_std(V(0.0f), sky_row_of_z<A>(z) * V(float(sky_rows - 1)));
  using std::min;  // int32 in the scalar path, xsimd's by argument-dependent lookup for batches
  const I i = min(simd::to_int_exact(fu), I(sky_columns - 1));
  const I j = min(simd::to_int_exact(fv), I(sky_rows - 2));
  const V a = fu - simd::to_float_exact(i), b = fv - simd::to_float_exact(j);
  const I p0 = (j * I(sky_columns) + i) * I(3);
  const I p1 = p0 + I(sky_columns * 3);
  const auto bilerp = [&](int c) {
    V v00, v10, v01, v11;
    simd::gather_pair(pairs, p0 + I(c), v00, v10);
    simd::gather_pair(pairs, p1 + I(c), v01, v11);
    const V lo = v00 + a * (v10 - v00);
    const V hi = v01 + a * (v11 - v01);
    return lo + b * (hi - lo);
  };
  return {bilerp(0), bilerp(1), bilerp(2)};
}

template <class A>
void sky_lookup_batch(const float* pairs, const float* x, const float* y, const float* z, std::size_t n, float* r,
                      float* g, float* b) noexcept {
  simd::for_batches<A>(n, [&](const auto& batch) HOULE_BATCH_BODY {
    const SkyRgb<A> c = sky_lookup<A>(pairs, batch.load(x), batch.load(y), batch.load(z, 1.0f));
    batch.store(r, c.r);
    batch.store(g, c.g);
    batch.store(b, c.b);
  });
}

}  // namespace houle::detail
