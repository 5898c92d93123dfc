// Compiled once per ISA (HOULE_ISA_ID set by cmake/HouleIsa.cmake) and once without it (scalar).
#define HOULE_ISA_SOURCE
#include "houle/simd/dispatch.hpp"
#include "colour_impl.hpp"
#include "foam_impl.hpp"
#include "optics_impl.hpp"
#include "ray_pack_impl.hpp"
#include "render_table.hpp"
#include "sand_impl.hpp"
#include "sea_light_impl.hpp"
#include "sky_impl.hpp"
#include "floor_hits_impl.hpp"
#include "under_light_impl.hpp"

namespace houle::detail {
namespace {
template <class A>
constexpr RenderTable make_render_table() {
  return {&fresnel_batch<A>, &reflect_refract_batch<A>, &sea_normals_batch<A>, &air_directions_batch<A>,
          &sky_lookup_batch<A>, &foam_cover_batch<A>,
          &water_mix_batch<A>, &sand_albedo_batch<A>, &sea_light_batch<A>, &sea_glint_batch<A>, &floor_hits_batch<A>,
          &under_light_batch<A>, &pack_rays_batch<A>};
}
}  // namespace
}  // namespace houle::detail

HOULE_DEFINE_ISA_TABLE(houle::detail::RenderTable, houle::detail::make_render_table)
