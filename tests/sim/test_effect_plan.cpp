// The effect plan (effect_plan.hpp): each stage is skipped exactly when the scene has nothing for it,
// and the counters of a skipped stage stay at zero.
#include <gtest/gtest.h>

#include "houle/sim/animation.hpp"
#include "houle/sim/effect_plan.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

using houle::Scene;

Scene deep_flat_sea() {
  Scene s;
  s.domain = {0.0, 0.0, 100.0, 100.0};
  s.floor.base.depth = 300.0;
  houle::WaveTrain t;
  t.period = 5.0;
  t.amplitude = 0.3;
  s.trains = {t, t};
  s.trains[1].direction_deg = 30.0;
  s.capillary.amplitude = 0.0;
  s.camera = houle::ViewCamera{{50.0, -20.0, 6.0}, {50.0, 50.0, 0.0}, 50.0, {}};
  return s;
}

const houle::Quality realtime = houle::quality_preset(houle::QualityPreset::realtime);

// The scene's sea surface computes no diffracted wave.
void expect_no_diffraction_work(const Scene& s) {
  const auto f = houle::trace_wave_field(s);
  ASSERT_TRUE(f.ok());
  const auto sea = houle::SeaSurface::build(s, f.value(), 1.0f);
  ASSERT_TRUE(sea.ok());
  EXPECT_EQ(sea->diffraction_work().pierheads, 0u);
  EXPECT_EQ(sea->diffraction_work().evaluations, 0u);
}

TEST(EffectPlan, DeepFlatSeaWithoutAnythingSkipsEveryOptionalStage) {
  const Scene s = deep_flat_sea();
  const houle::EffectPlan p = houle::plan_effects(s, realtime);
  ASSERT_EQ(p.train_rays.size(), 2u);
  EXPECT_FALSE(p.train_rays[0] || p.train_rays[1]);
  EXPECT_FALSE(p.ray_tracing);
  EXPECT_FALSE(p.diffraction);
  EXPECT_FALSE(p.wall_reflection);
  EXPECT_FALSE(p.capillary_noise);
  EXPECT_FALSE(p.surf);  // analytic trains never break here: no surf map, no foam work per pixel
  EXPECT_FALSE(p.refraction);  // 300 m of clear water and no floor grid: nothing to see below
  EXPECT_TRUE(p.specular);
  EXPECT_FALSE(p.shadows);     // the sun is up and nothing stands above the water
  EXPECT_FALSE(p.reflect_objects);
  const houle::Quality q = houle::planned_quality(p, realtime);
  EXPECT_FALSE(q.render.shadows);
  EXPECT_FALSE(q.render.reflect_objects);
  // The counters: no ray, no sample, no step, no diffraction coefficient, no reflected ray.
  const auto f = houle::trace_wave_field(s, 2);
  ASSERT_TRUE(f.ok());
  EXPECT_TRUE(f->trains[0].analytic && f->trains[1].analytic);
  EXPECT_EQ(f->stats.rays, 0u);
  EXPECT_EQ(f->stats.samples, 0u);
  EXPECT_EQ(f->stats.steps, 0u);
  EXPECT_EQ(f->stats.reflected_rays, 0u);
  EXPECT_TRUE(f->reflections.empty());
  const auto sea = houle::SeaSurface::build(s, f.value());
  ASSERT_TRUE(sea.ok());
  EXPECT_EQ(sea->diffraction_work().pierheads, 0u);
  EXPECT_EQ(sea->diffraction_work().evaluations, 0u);
  // The animation builds no noise frame.
  auto anim = houle::Animation::create(s, realtime, 16, 8, 1);
  ASSERT_TRUE(anim.ok());
  houle::Framebuffer fb(16, 8);
  anim->render(0.5, fb);
  EXPECT_EQ(anim->noise_frames(), 0u);
}

TEST(EffectPlan, EachStageFollowsWhatTheSceneHas) {
  Scene s = deep_flat_sea();
  s.capillary.amplitude = 0.01;
  EXPECT_TRUE(houle::plan_effects(s, realtime).capillary_noise);
  s.capillary.max_octaves = 0;
  EXPECT_FALSE(houle::plan_effects(s, realtime).capillary_noise);
  s.capillary.max_octaves = 4;
  auto anim = houle::Animation::create(s, realtime, 16, 8, 1);
  ASSERT_TRUE(anim.ok());
  houle::Framebuffer fb(16, 8);
  anim->render(0.5, fb);
  EXPECT_EQ(anim->noise_frames(), 1u);

  // A shallow floor is seen through the water; a submerged sphere too.
  Scene shallow = deep_flat_sea();
  shallow.floor.base.depth = 15.0;
  EXPECT_TRUE(houle::plan_effects(shallow, realtime).refraction);
  Scene sphere = deep_flat_sea();
  sphere.spheres.push_back(houle::Sphere{{50.0, 50.0, -1.0}, 2.0, {}});
  houle::EffectPlan p = houle::plan_effects(sphere, realtime);
  EXPECT_TRUE(p.refraction);
  EXPECT_TRUE(p.shadows);  // it stands above the water and can shade and be reflected
  EXPECT_TRUE(p.reflect_objects);
  EXPECT_FALSE(houle::plan_effects(sphere, houle::quality_preset(houle::QualityPreset::draft)).shadows);  // draft: off
  // A floating sphere is partly under the water whatever its centre's z says; a sea state in deep
  // flat water is analytic trains, none traced.
  Scene buoy = deep_flat_sea();
  buoy.spheres.push_back(houle::Sphere{{50.0, 50.0, 30.0}, 1.0, {}});
  EXPECT_FALSE(houle::plan_effects(buoy, realtime).refraction);
  buoy.spheres[0].floats = true;
  EXPECT_TRUE(houle::plan_effects(buoy, realtime).refraction);
  buoy.sea_states.push_back(houle::SeaState{});
  const auto expanded = houle::validate(buoy);
  ASSERT_TRUE(expanded.ok());
  p = houle::plan_effects(expanded.value(), realtime);
  EXPECT_EQ(p.train_rays.size(), 2u + houle::SeaState{}.components);
  EXPECT_FALSE(p.ray_tracing);

  // The sun below the horizon: no glint, but shadow rays stay (they run downwards, into the floor).
  Scene night = deep_flat_sea();
  night.sun.elevation_deg = -5.0;
  p = houle::plan_effects(night, realtime);
  EXPECT_FALSE(p.specular);
  EXPECT_TRUE(p.shadows);

  // A beach: rays, no pierhead, no reflection.
  Scene beach = deep_flat_sea();
  beach.floor.base.kind = houle::FloorKind::planar_beach;
  beach.floor.base.depth = 8.0;
  beach.floor.base.shoreline = {0.0, 150.0};
  p = houle::plan_effects(beach, realtime);
  EXPECT_TRUE(p.ray_tracing);
  EXPECT_FALSE(p.diffraction);
  EXPECT_FALSE(p.wall_reflection);
  expect_no_diffraction_work(beach);

  // The paper's Fig. 4: a rigid wall with its pierhead in the water; the sea surface diffracts the
  // train round it at every grid node the diffracted wave reaches.
  Scene fig4 = houle::paper_fig4();
  p = houle::plan_effects(fig4, realtime);
  EXPECT_TRUE(p.ray_tracing && p.diffraction && p.wall_reflection && p.surf);
  {
    const auto f = houle::trace_wave_field(fig4);
    ASSERT_TRUE(f.ok());
    const auto sea = houle::SeaSurface::build(fig4, f.value(), 1.0f);
    ASSERT_TRUE(sea.ok());
    EXPECT_EQ(sea->diffraction_work().pierheads, 1u);
    EXPECT_GT(sea->diffraction_work().evaluations, 101u * 101u / 2);  // over half the 1 m grid
    EXPECT_LE(sea->diffraction_work().evaluations, 101u * 101u);
  }
  fig4.dwt.diffraction = false;
  fig4.walls[0].reflection = 0.0;
  p = houle::plan_effects(fig4, realtime);
  EXPECT_TRUE(p.ray_tracing);
  EXPECT_FALSE(p.diffraction || p.wall_reflection);
  const auto f = houle::trace_wave_field(fig4);
  ASSERT_TRUE(f.ok());
  EXPECT_GT(f->stats.rays, 0u);
  EXPECT_EQ(f->stats.reflected_rays, 0u);
  expect_no_diffraction_work(fig4);
}

}  // namespace

// The wave model: auto marches the parabolic model only over floors whose rays cross, and the sea
// surface does what the plan says (docs/physics.md 10.6).
TEST(EffectPlan, AutoMarchesTheParabolicModelOnlyWhereRaysCross) {
  Scene beach = deep_flat_sea();
  beach.floor.base = {houle::FloorKind::planar_beach, 12.0, 0.05, 90.0, {0.0, 150.0}};
  Scene shoal = beach;
  shoal.floor.shoals.push_back(houle::Shoal{{50.0, 50.0}, 10.0, 10.0, 0.0, 4.0});
  const houle::EffectPlan on_beach = houle::plan_effects(beach, realtime), on_shoal = houle::plan_effects(shoal, realtime);
  EXPECT_EQ(on_beach.wave_model.kind, houle::WaveModelKind::rays);
  EXPECT_EQ(on_shoal.wave_model.kind, houle::WaveModelKind::parabolic);
  EXPECT_NE(on_shoal.wave_model.why.find("auto"), std::string_view::npos);
  for (const Scene* s : {&beach, &shoal}) {
    const auto f = houle::trace_wave_field(*s);
    ASSERT_TRUE(f.ok());
    const auto sea = houle::SeaSurface::build(*s, f.value(), 1.0f);
    ASSERT_TRUE(sea.ok());
    for (const houle::TrainField& t : sea->trains()) {
      EXPECT_EQ(t.model, houle::plan_effects(*s, realtime).wave_model.kind);
      EXPECT_EQ(t.model_nodes > 0, t.model == houle::WaveModelKind::parabolic);
    }
  }
  // Chosen explicitly, each model is used whatever the floor.
  beach.wave_model.kind = houle::WaveModelKind::parabolic;
  shoal.wave_model.kind = houle::WaveModelKind::rays;
  EXPECT_EQ(houle::plan_effects(beach, realtime).wave_model.kind, houle::WaveModelKind::parabolic);
  EXPECT_EQ(houle::plan_effects(shoal, realtime).wave_model.kind, houle::WaveModelKind::rays);
}
