// Effect plan: which stages a scene needs, decided once from the scene and the quality before any
// work is done, so that a stage with nothing to do costs nothing (a deep flat sea builds no rays, a
// scene without pierheads evaluates no diffraction coefficient, no ripples means no noise frame).
// Animation::create follows it; `houle info` prints it; the tracer's, sea surface's and renderer's
// counters prove a skipped stage did no work (DwtStats: rays, samples, reflected_rays = 0;
// SeaSurface::diffraction_work: no pierhead, no evaluation).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "houle/sim/animation.hpp"
#include "houle/sim/scene.hpp"
#include "houle/sim/wave_rays.hpp"

namespace houle {

struct EffectPlan {
  // ---- Scene build (sim) ----
  /// Per train: 1 traced (refraction, walls), 0 analytic straight crests (bytes: gcc 12 warns falsely
  /// of null dereferences in vector<bool>).
  std::vector<std::uint8_t> train_rays;
  bool ray_tracing = false;      ///< some train is traced
  /// What computes the traced trains' fields (rays or the parabolic model), and why (docs/physics.md 10.6).
  TrainModel wave_model;
  bool diffraction = false;      ///< a pierhead in water meets a traced train (DwtSettings::diffraction on)
  bool wall_reflection = false;  ///< a wall with alpha > 0 meets a traced train
  bool capillary_noise = false;  ///< ripples with amplitude > 0 and at least one octave
  /// Surf and foam can exist: some train is traced (only traced trains break, and walls meet only
  /// them). The scene build then finds where (SeaSurface::surf_map); nothing breaking costs nothing.
  bool surf = false;
  // ---- Per frame (renderer) ----
  /// Something under the surface can be seen: a submerged object or wall, or a floor shallower than
  /// the depth where the round trip through the water leaves less than 1/1024 of the light.
  /// Reported only: the renderer always traces the refracted ray (it sees I_sea when nothing is hit).
  bool refraction = false;
  bool specular = false;         ///< the sun is above the horizon: glint and direct light exist
  bool shadows = false;          ///< the quality asks for shadows, the sun is up and something casts them
  bool reflect_objects = false;  ///< the quality asks for it and there is an object or wall to reflect
};

/// The plan of a valid scene at a quality.
EffectPlan plan_effects(const Scene& scene, const Quality& quality);

/// The quality with the render stages the plan skips switched off (shadows, object reflections):
/// what Animation::create renders with. The image is the same as with `quality`.
Quality planned_quality(const EffectPlan& plan, Quality quality) noexcept;

}  // namespace houle
