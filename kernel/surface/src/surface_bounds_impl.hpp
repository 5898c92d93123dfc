// Column statistics for the SurfaceFrame's bounds pass, written once for every width (included by
// surface_isa.cpp): elementwise over node columns, so every lane is independent and the result is the
// same on every ISA (min, max and |.| of differences only).
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/simd/simd.hpp"
#include "surface_bounds.hpp"

namespace houle::detail {

/// See ColumnStatsJob.
template <class A>
void surface_column_stats(const ColumnStatsJob& job) noexcept {
  using V = simd::vfloat<A>;
  constexpr std::size_t W = simd::width<A>;
  for (std::size_t i = job.a; i <= job.b; i += W) {
    V lo = simd::load<A>(job.rows + i), hi = lo, dx(0.0f), dy(0.0f);
    V cur = lo;
    for (std::uint32_t j = 0; j < job.count; ++j) {
      const float* r = job.rows + j * job.stride + i;
      if (j > 0) {
        const V next = simd::load<A>(r);
        const V d = simd::abs(next - cur);
        dy = simd::max_as_std(dy, d);
        cur = next;
        lo = simd::min_as_std(lo, cur);
        hi = simd::max_as_std(hi, cur);
      }
      const V e = simd::abs(simd::load<A>(r + 1) - cur);
      dx = simd::max_as_std(dx, e);
    }
    simd::store<A>(job.lo + i, lo);
    simd::store<A>(job.hi + i, hi);
    simd::store<A>(job.dx + i, dx);
    simd::store<A>(job.dy + i, dy);
  }
}

}  // namespace houle::detail
