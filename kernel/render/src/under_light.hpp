// The light on what a sea pixel's ray into the water meets, and whether the sun reaches the pixel's
// own sea hit, for a row a packet at a time (templates in under_light_impl.hpp; docs/rendering.md
// 3.4, 3.5). The boxes' and spheres' shadows are asked of the shadow masks in lanes; where a mask says
// a caster may be in the way, the lane is left to the renderer's exact shadow ray.
#pragma once
#include <cstddef>

#include "houle/runtime/isa.hpp"
#include "shadow_mask.hpp"

namespace houle::detail {

/// The scene's light under the sea, in the renderer's relative units (renderer.cpp).
struct UnderLightParams {
  float ambient[3];    ///< the sky's light after entering the sea, on a white horizontal surface
  float sun_rgb[3];    ///< the sun's after entering it, on a white surface facing it
  float sun_water[3];  ///< towards the sun under a flat sea, unit
  float sun[3];        ///< towards the sun in air, unit
  float casters_top;   ///< m, the highest point of a box or sphere (-inf: none)
  bool shadows;
  ShadowMaskView sun_mask, sun_water_mask;  ///< along sun and sun_water
};

/// A row of pixels. Only pixels with side > 0 (a sea hit seen from above) are lit here.
struct UnderLightInput {
  const float* side;
  const float *x, *y, *z;     ///< the sea hit
  const float *nx, *ny, *nz;  ///< the sea's normal there
  const float* t;             ///< m from the camera to the sea hit
  const float* met;           ///< > 0: the ray into the water meets a surface (the floor, a box, a sphere)
  const float *dx, *dy, *dz;  ///< the ray into the water
  const float* hit_t;         ///< m along it to that surface
  const float *hit_nx, *hit_ny, *hit_nz;  ///< the surface's normal
  const float *albedo_r, *albedo_g, *albedo_b;
};

/// lit: 1 where the sun reaches the sea hit. r, g, b: the light the surface met sends back up the ray
/// into the water, and path: the m of water the sun's light crossed to reach it. ask: where a shadow
/// mask says a caster may be in the way, 1 (whether the sun reaches the sea hit), 2 (the surface met's
/// light) or 3 (both), which the renderer works out itself. All 0 where they do not apply (pixels not
/// lit here, no surface met).
struct UnderLightOutput {
  float *lit, *ask, *r, *g, *b, *path;
};

void under_light(const UnderLightParams& p, const UnderLightInput& in, std::size_t n, UnderLightOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void under_light(Isa isa, const UnderLightParams& p, const UnderLightInput& in, std::size_t n,
                 UnderLightOutput out) noexcept;

}  // namespace houle::detail
