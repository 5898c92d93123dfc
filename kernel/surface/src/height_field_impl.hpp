// The loop every height-field kernel shares: points in whole batches, the tail through the same
// full-width code on a padded copy so that every lane is computed alike.
#pragma once
#include <algorithm>
#include <cstddef>

#include "houle/surface/gerstner.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
struct HeightFieldPoint {
  simd::vfloat<A> height, grad_x, grad_y;
};

/// out[i] = point(x[i], y[i]) for i < n; `point` maps (vfloat<A> x, vfloat<A> y) to a HeightFieldPoint<A>.
template <class A, class Point>
inline void eval_height_field(const float* x, const float* y, std::size_t n, GerstnerOutput out, Point point) {
  constexpr std::size_t W = simd::width<A>;
  std::size_t i = 0;
  for (; i + W <= n; i += W) {
    const HeightFieldPoint<A> p = point(simd::load<A>(x + i), simd::load<A>(y + i));
    simd::store<A>(out.height + i, p.height);
    simd::store<A>(out.grad_x + i, p.grad_x);
    simd::store<A>(out.grad_y + i, p.grad_y);
  }
  if (i < n) {
    alignas(64) float tx[W] = {}, ty[W] = {}, th[W], tgx[W], tgy[W];
    std::copy(x + i, x + n, tx);
    std::copy(y + i, y + n, ty);
    const HeightFieldPoint<A> p = point(simd::load<A>(tx), simd::load<A>(ty));
    simd::store<A>(th, p.height);
    simd::store<A>(tgx, p.grad_x);
    simd::store<A>(tgy, p.grad_y);
    std::copy(th, th + (n - i), out.height + i);
    std::copy(tgx, tgx + (n - i), out.grad_x + i);
    std::copy(tgy, tgy + (n - i), out.grad_y + i);
  }
}

}  // namespace houle::detail
