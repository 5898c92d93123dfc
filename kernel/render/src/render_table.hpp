// The render room's per-ISA function table (see houle/simd/dispatch.hpp).
#pragma once
#include <cstddef>

#include "colour_impl.hpp"
#include "foam.hpp"
#include "houle/render/optics.hpp"
#include "sand.hpp"
#include "sea_light.hpp"
#include "floor_hits.hpp"
#include "ray_pack.hpp"
#include "under_light.hpp"

namespace houle::detail {

struct RenderTable {
  void (*fresnel_batch)(const float*, float, float*, std::size_t) noexcept;
  void (*reflect_refract_batch)(const ReflectRefractInput&, std::size_t, float, float, ReflectRefractOutput) noexcept;
  void (*sea_normals_batch)(const SeaNormalsInput&, std::size_t, SeaNormalsOutput) noexcept;
  void (*air_directions_batch)(const AirDirectionsInput&, std::size_t, float, AirDirectionsOutput) noexcept;
  void (*sky_lookup_batch)(const float* pairs, const float*, const float*, const float*, std::size_t, float*, float*,
                           float*) noexcept;
  void (*foam_cover_batch)(const SurfView&, const FoamInput&, std::size_t, float, float*) noexcept;
  void (*water_mix_batch)(const WaterTable&, const WaterMixInput&, std::size_t, WaterMixOutput) noexcept;
  void (*sand_albedo_batch)(const LinearRgb&, const SandInput&, std::size_t, SandOutput) noexcept;
  void (*sea_light_batch)(const SeaLightParams&, const SeaLightInput&, std::size_t, SeaLightOutput) noexcept;
  void (*sea_glint_batch)(const SeaLightParams&, const SeaLightInput&, const float*, std::size_t, SeaLightOutput) noexcept;
  void (*floor_hits_batch)(const FloorGridView&, const ObjectBounds&, const FloorRays&, std::size_t, FloorHits) noexcept;
  void (*under_light_batch)(const UnderLightParams&, const UnderLightInput&, std::size_t, UnderLightOutput) noexcept;
  std::size_t (*pack_rays_batch)(const RayPackInput&, std::size_t, const RayPackParams&, RayPackOutput) noexcept;
};

}  // namespace houle::detail
