// The loop every height-field kernel shares (simd::for_batches: the tail padded with zeros).
#pragma once
#include <cstddef>

#include "houle/surface/gerstner.hpp"
#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"

namespace houle::detail {

template <class A>
struct HeightFieldPoint {
  simd::vfloat<A> height, grad_x, grad_y;
};

/// out[i] = point(x[i], y[i]) for i < n; `point` maps (vfloat<A> x, vfloat<A> y) to a HeightFieldPoint<A>.
template <class A, class Point>
inline void eval_height_field(const float* x, const float* y, std::size_t n, GerstnerOutput out, Point point) {
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    const HeightFieldPoint<A> p = point(b.load(x), b.load(y));
    b.store(out.height, p.height);
    b.store(out.grad_x, p.grad_x);
    b.store(out.grad_y, p.grad_y);
  });
}

}  // namespace houle::detail
