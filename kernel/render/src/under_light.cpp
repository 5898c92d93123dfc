// The dispatched light under the sea (templates in under_light_impl.hpp).
#include "under_light.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"

namespace houle::detail {

namespace {
void check_under_light(const UnderLightInput& in, std::size_t n, const UnderLightOutput& out) noexcept {
  const float* arrays[] = {in.side, in.x, in.y, in.z, in.nx, in.ny, in.nz, in.t, in.met, in.dx, in.dy, in.dz,
                           in.hit_t, in.hit_nx, in.hit_ny, in.hit_nz, in.albedo_r, in.albedo_g, in.albedo_b,
                           out.lit, out.ask, out.r, out.g, out.b, out.path};
  bool all = true;
  for (const float* a : arrays) all = all && a != nullptr;
  HOULE_ASSERT(n == 0 || all, "under_light: n floats in every array");
}
}  // namespace

void under_light(const UnderLightParams& p, const UnderLightInput& in, std::size_t n, UnderLightOutput out) noexcept {
  check_under_light(in, n, out);
  simd::active_table<RenderTable>().under_light_batch(p, in, n, out);
}

void under_light(Isa isa, const UnderLightParams& p, const UnderLightInput& in, std::size_t n,
                 UnderLightOutput out) noexcept {
  check_under_light(in, n, out);
  simd::table_for<RenderTable>(isa).under_light_batch(p, in, n, out);
}

}  // namespace houle::detail
