// The secondary rays of a row's sea hits, packed for the kernels that trace them (templates in
// ray_pack_impl.hpp): only some pixels send a ray (sea hits, and not under total reflection), so the
// rays are compacted, each with its pixel's index.
#pragma once
#include <cstddef>
#include <cstdint>

#include "houle/runtime/isa.hpp"

namespace houle::detail {

/// One row: side (> 0 a sea hit seen from above, < 0 from below, 0 none), the Fresnel reflectance kr,
/// the hit's distance t, the hit point, its normal, and the ray's direction for each side.
struct RayPackInput {
  const float *side, *kr, *t;
  const float *x, *y, *z, *nx, *ny, *nz;
  const float *above_x, *above_y, *above_z;  ///< where side > 0
  const float *below_x, *below_y, *below_z;  ///< where side < 0
};
/// `into_water`: the ray into the water (refracted from above, reflected from below), from the hit
/// moved off the surface against the normal; otherwise the ray into the air, moved along it. The side
/// whose ray is the refracted one sends none where kr >= 1 (total reflection, or a NaN).
struct RayPackParams {
  bool into_water = true;
  float reach = 0.0f;  ///< m, every ray's
};
/// Rays k = 0 .. count - 1 (the return value), in the order of their pixels. Every array has room for
/// n rays rounded up to a multiple of 16.
struct RayPackOutput {
  float *ox, *oy, *oz, *dx, *dy, *dz, *reach;
  std::uint32_t* pixel;
};
/// The ray of each pixel that sends one: from (x, y, z) moved (1e-3 + 1e-4 t) m off the surface.
std::size_t pack_rays(const RayPackInput& in, std::size_t n, const RayPackParams& p, RayPackOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
std::size_t pack_rays(Isa isa, const RayPackInput& in, std::size_t n, const RayPackParams& p, RayPackOutput out) noexcept;

}  // namespace houle::detail
