// Primary ray directions a row at a time, written once for every width (included by surface_isa.cpp).
// The operations of camera_ray in the same order, with a correctly rounded sqrt and division and no
// contraction, so every ISA gives the scalar path's bits (and camera_ray's).
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/simd.hpp"
#include "houle/surface/camera.hpp"

namespace houle::detail {

template <class A>
void camera_row_rays(const Camera& c, std::uint32_t row, std::uint32_t x0, std::size_t n, float sub_x, float sub_y,
                     float* dx, float* dy, float* dz) noexcept {
  using V = simd::vfloat<A>;
  // Image-plane point at unit distance: forward + a right + b up, a and b in pixel_scale units from
  // the image centre; the row's part (forward + b up) is shared.
  const float b = (0.5f * float(c.height) - (float(row) + sub_y)) * c.pixel_scale;
  const V vx(c.forward[0] + b * c.up[0]), vy(c.forward[1] + b * c.up[1]), vz(c.forward[2] + b * c.up[2]);
  const V first = V(float(x0)), half_w = V(0.5f * float(c.width));
  simd::for_batches<A>(n, [&](const auto& batch) HOULE_BATCH_BODY {
    const V a = ((first + batch.indices() + sub_x) - half_w) * c.pixel_scale;
    const V x = vx + a * c.right[0], y = vy + a * c.right[1], z = vz + a * c.right[2];
    const V inv = simd::div(V(1.0f), simd::sqrt(x * x + y * y + z * z));
    batch.store(dx, x * inv);
    batch.store(dy, y * inv);
    batch.store(dz, z * inv);
  });
}

}  // namespace houle::detail
