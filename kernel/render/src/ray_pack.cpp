// The dispatched ray packing (templates in ray_pack_impl.hpp).
#include "ray_pack.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

namespace {
void check_pack(const RayPackInput& in, std::size_t n, const RayPackOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.side != nullptr && in.kr != nullptr && in.t != nullptr && in.x != nullptr &&
                          in.y != nullptr && in.z != nullptr && in.nx != nullptr && in.ny != nullptr &&
                          in.nz != nullptr && in.above_x != nullptr && in.above_y != nullptr &&
                          in.above_z != nullptr && in.below_x != nullptr && in.below_y != nullptr &&
                          in.below_z != nullptr && out.ox != nullptr && out.oy != nullptr && out.oz != nullptr &&
                          out.dx != nullptr && out.dy != nullptr && out.dz != nullptr && out.reach != nullptr &&
                          out.pixel != nullptr),
               "pack_rays: n floats in every array");
}
}  // namespace

std::size_t pack_rays(const RayPackInput& in, std::size_t n, const RayPackParams& p, RayPackOutput out) noexcept {
  check_pack(in, n, out);
  return simd::active_table<RenderTable>().pack_rays_batch(in, n, p, out);
}

std::size_t pack_rays(Isa isa, const RayPackInput& in, std::size_t n, const RayPackParams& p, RayPackOutput out) noexcept {
  check_pack(in, n, out);
  return simd::table_for<RenderTable>(isa).pack_rays_batch(in, n, p, out);
}

}  // namespace houle::detail
