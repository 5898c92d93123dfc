// Secondary rays packed (ray_pack.hpp), written once for every width (included by render_isa.cpp).
// The origin is the scalar renderer's expression, p + offset (+-n): every ISA gives the same bits.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/simd/batch_loop.hpp"
#include "houle/simd/compress.hpp"
#include "houle/simd/gather.hpp"
#include "houle/simd/simd.hpp"
#include "ray_pack.hpp"

namespace houle::detail {

template <class A>
std::size_t pack_rays_batch(const RayPackInput& in, std::size_t n, const RayPackParams& p, RayPackOutput out) noexcept {
  std::size_t count = 0;
  simd::for_batches<A>(n, [&](const auto& b) HOULE_BATCH_BODY {
    using V = simd::vfloat<A>;
    const V zero(0.0f), side = b.load(in.side);
    const auto above = side > zero;
    // The refracted ray's side: from above into the water, from below into the air.
    const auto refracting = p.into_water ? above : side < zero;
    const auto sends = (side != zero) & !(refracting & !(b.load(in.kr) < V(1.0f)));
    if (!simd::any(sends)) return;
    const V offset = V(1e-3f) + V(1e-4f) * b.load(in.t);
    V nx = b.load(in.nx), ny = b.load(in.ny), nz = b.load(in.nz);
    if (p.into_water) nx = -nx, ny = -ny, nz = -nz;
    const auto pack = [&](float* dst, V v) { return simd::compress_store(dst + count, v, sends); };
    pack(out.ox, b.load(in.x) + offset * nx);
    pack(out.oy, b.load(in.y) + offset * ny);
    pack(out.oz, b.load(in.z) + offset * nz);
    pack(out.dx, simd::select(above, b.load(in.above_x), b.load(in.below_x)));
    pack(out.dy, simd::select(above, b.load(in.above_y), b.load(in.below_y)));
    pack(out.dz, simd::select(above, b.load(in.above_z), b.load(in.below_z)));
    pack(out.reach, V(p.reach));
    count += simd::compress_store(out.pixel + count, simd::to_int_exact(b.indices()), sends);
  });
  return count;
}

}  // namespace houle::detail
