// The light a sea hit seen from above sends to the camera (docs/rendering.md 3.1), for a row of
// pixels a packet at a time (templates in sea_light_impl.hpp): what the rays into the air and into
// the water bring, split by Fresnel, with the sun's glint and the surf's foam on top.
#pragma once
#include <cstddef>

#include "houle/runtime/isa.hpp"

namespace houle::detail {

/// A row of pixels. Only pixels with side > 0 (a sea hit seen from above) are lit here.
struct SeaLightInput {
  const float* side;
  const float* kr;                        ///< Fresnel reflectance
  const float *sky_r, *sky_g, *sky_b;     ///< the sky along the ray into the air, unscaled (SkyLut)
  const float* air_hit;                   ///< > 0: the ray into the air meets something, lit as reflected_*
  const float *reflected_r, *reflected_g, *reflected_b;
  const float *under_r, *under_g, *under_b;  ///< what the ray into the water brings up (used where kr < 1)
  const float* lit;                       ///< > 0: the sun reaches the hit
  const float *nx, *ny, *nz;              ///< the surface's normal
  const float *dx, *dy, *dz;              ///< the ray from the camera
  const float* rough;                     ///< the slope variance the grid's LOD leaves out
  const float* foam;                      ///< the foam cover; null: no surf
};

/// The scene's light in the renderer's relative units (renderer.cpp) and the most slope variance the
/// noise's LOD can leave out anywhere (the glint test's widest lobe).
struct SeaLightParams {
  float sky_scale[3], sun_rgb[3], ambient[3];
  float sun[3];  ///< towards the sun, unit
  float dropped_max;
};

/// r, g, b: the light without the glint, for every pixel lit here (the others' entries are left
/// undefined). glint_lobe: 1 where the sun's glint lobe, as wide as dropped_max allows, may reach the
/// camera (the renderer then works out the pixel's own slope variance and, where its lobe still may,
/// adds the glint with sea_glint), 0 elsewhere.
struct SeaLightOutput {
  float *r, *g, *b, *glint_lobe;
};

void sea_light(const SeaLightParams& p, const SeaLightInput& in, std::size_t n, SeaLightOutput out) noexcept;
/// Whether pixel i's glint lobe for slope variance `variance` may reach the camera: beyond it the lobe
/// is below e^-30 of its peak.
bool glint_lobe_at(const SeaLightParams& p, const SeaLightInput& in, std::size_t i, float variance) noexcept;
/// The pixels with out.glint_lobe[i] > 0 lit again, with the sun's glint (pi sun_glint, slope variance
/// glint_variance[i]) added before the foam; the others are left as they are.
void sea_glint(const SeaLightParams& p, const SeaLightInput& in, const float* glint_variance, std::size_t n,
               SeaLightOutput out) noexcept;
/// The same on a given ISA (it must be supported): for tests and benchmarks.
void sea_light(Isa isa, const SeaLightParams& p, const SeaLightInput& in, std::size_t n, SeaLightOutput out) noexcept;
void sea_glint(Isa isa, const SeaLightParams& p, const SeaLightInput& in, const float* glint_variance, std::size_t n,
               SeaLightOutput out) noexcept;

}  // namespace houle::detail
