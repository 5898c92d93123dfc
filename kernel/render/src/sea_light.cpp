// The dispatched light of sea hits seen from above and their glint, and the glint lobe's test pixel by
// pixel (templates in sea_light_impl.hpp).
#include "sea_light.hpp"

#include "houle/runtime/assert.hpp"
#include "houle/simd/dispatch.hpp"
#include "render_table.hpp"
#include "sea_light_impl.hpp"

namespace houle::detail {

namespace {
void check_sea_light(const SeaLightInput& in, std::size_t n, const SeaLightOutput& out) noexcept {
  HOULE_ASSERT(n == 0 || (in.side != nullptr && in.kr != nullptr && in.sky_r != nullptr && in.sky_g != nullptr &&
                          in.sky_b != nullptr && in.air_hit != nullptr && in.reflected_r != nullptr &&
                          in.reflected_g != nullptr && in.reflected_b != nullptr && in.under_r != nullptr &&
                          in.under_g != nullptr && in.under_b != nullptr && in.lit != nullptr && in.nx != nullptr &&
                          in.ny != nullptr && in.nz != nullptr && in.dx != nullptr && in.dy != nullptr &&
                          in.dz != nullptr && in.rough != nullptr && out.r != nullptr && out.g != nullptr &&
                          out.b != nullptr && out.glint_lobe != nullptr),
               "sea_light: n floats in every array (foam may be null)");
}

SeaLightLanes<simd::scalar> lanes_at(const SeaLightParams& p, const SeaLightInput& in, std::size_t i) {
  return sea_light_lanes<simd::scalar>(p, in, [i](const float* a) { return a[i]; });
}
}  // namespace

void sea_light(const SeaLightParams& p, const SeaLightInput& in, std::size_t n, SeaLightOutput out) noexcept {
  check_sea_light(in, n, out);
  simd::active_table<RenderTable>().sea_light_batch(p, in, n, out);
}

void sea_light(Isa isa, const SeaLightParams& p, const SeaLightInput& in, std::size_t n, SeaLightOutput out) noexcept {
  check_sea_light(in, n, out);
  simd::table_for<RenderTable>(isa).sea_light_batch(p, in, n, out);
}

bool glint_lobe_at(const SeaLightParams& p, const SeaLightInput& in, std::size_t i, float variance) noexcept {
  return glint_lobe<simd::scalar>(p, lanes_at(p, in, i), variance);
}

void sea_glint(const SeaLightParams& p, const SeaLightInput& in, const float* glint_variance, std::size_t n,
               SeaLightOutput out) noexcept {
  check_sea_light(in, n, out);
  HOULE_ASSERT(n == 0 || glint_variance != nullptr, "sea_glint: n floats in glint_variance");
  simd::active_table<RenderTable>().sea_glint_batch(p, in, glint_variance, n, out);
}

void sea_glint(Isa isa, const SeaLightParams& p, const SeaLightInput& in, const float* glint_variance, std::size_t n,
               SeaLightOutput out) noexcept {
  check_sea_light(in, n, out);
  HOULE_ASSERT(n == 0 || glint_variance != nullptr, "sea_glint: n floats in glint_variance");
  simd::table_for<RenderTable>(isa).sea_glint_batch(p, in, glint_variance, n, out);
}

}  // namespace houle::detail
