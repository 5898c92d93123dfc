// The effect plan (effect_plan.hpp).
#include "houle/sim/effect_plan.hpp"

#include <algorithm>
#include <cmath>

#include "houle/render/colour.hpp"
#include "houle/sim/bathymetry.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {
namespace {

// Depth below which the floor cannot be told from I_sea: the light's round trip (down to the floor
// and back up, at least twice the depth) keeps less than 1/1024 of it at the least absorbed
// wavelength.
double floor_visibility_depth(const Water& water) {
  const Spectrum a = water_absorption(water.extra_absorption);
  const double a_min = *std::min_element(a.begin(), a.end());
  return std::log(1024.0) / (2.0 * a_min);
}

}  // namespace

EffectPlan plan_effects(const Scene& scene, const Quality& quality) {
  EffectPlan p;
  p.train_rays.assign(scene.trains.size(), 0);
  for (std::size_t t = 0; t < scene.trains.size(); ++t) {
    p.train_rays[t] = !scene.dwt.analytic_shortcut ? scene.trains[t].amplitude > 0.0 : train_needs_rays(scene, t);
    p.ray_tracing = p.ray_tracing || p.train_rays[t];
  }
  p.wave_model = scene_wave_model(scene);
  p.diffraction = p.ray_tracing && scene_has_pierheads(scene);
  p.wall_reflection = p.ray_tracing && scene_has_reflecting_walls(scene);
  p.capillary_noise = scene.capillary.amplitude > 0.0 && scene.capillary.max_octaves > 0;
  p.surf = p.ray_tracing;

  const Bathymetry floor(scene.floor);
  const double shallowest = floor.min_depth_bound(scene.domain);
  // The renderer has a floor grid unless the floor is uniform and deep (render_scene.cpp).
  const bool floor_grid = !floor.uniform() || scene.floor.base.depth < 200.0;
  bool submerged = !scene.walls.empty();  // wall blocks reach 2 m below still water
  for (const Box& b : scene.boxes) submerged = submerged || b.floats || b.center.z - b.half_extent.z < 0.0;
  for (const Sphere& s : scene.spheres) submerged = submerged || s.floats || s.center.z - s.radius < 0.0;
  p.refraction = submerged || (floor_grid && shallowest < floor_visibility_depth(scene.water));

  p.specular = scene.sun.elevation_deg > 0.0;
  // What stands above the water: the only things a ray leaving the sea upwards can meet.
  const bool above = !scene.walls.empty() || !scene.boxes.empty() || !scene.spheres.empty() || (floor_grid && shallowest <= 0.0);
  // With the sun below the horizon a shadow ray towards it runs downwards and may meet the floor, so
  // only a risen sun over nothing that stands up has no shadows to trace.
  p.shadows = quality.render.shadows && (above || !p.specular);
  p.reflect_objects = quality.render.reflect_objects && above;
  return p;
}

Quality planned_quality(const EffectPlan& plan, Quality quality) noexcept {
  quality.render.shadows = plan.shadows;
  quality.render.reflect_objects = plan.reflect_objects;
  return quality;
}

}  // namespace houle
