// Properties over random valid scenes (seeded, the same scenes on every machine): no NaN or Inf in
// the traced rays, the sea surface or any pixel; amplitude within the breaking limit; no energy
// created at caustics (refraction capped). The worst values over all scenes are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "surface_checks.hpp"
#include "emulation.hpp"

namespace {

constexpr int scene_count = int(houle::test::emulation_scaled(12));

// std::uniform_real_distribution differs between standard libraries; this does not.
class Random {
 public:
  explicit Random(std::uint32_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(engine_() >> 5) * 0x1p-27; }
  int integer(int lo, int hi) { return lo + int(engine_() % std::uint32_t(hi - lo + 1)); }

 private:
  std::mt19937 engine_;
};

houle::Scene random_scene(Random& r) {
  houle::Scene s;
  const double wx = r.uniform(20.0, 160.0), wy = r.uniform(20.0, 160.0);
  s.domain = {-0.5 * wx, 0.0, 0.5 * wx, wy};
  houle::FloorBase& b = s.floor.base;
  b.depth = r.uniform(0.5, 40.0);
  if (r.integer(0, 3) > 0) {
    b.kind = houle::FloorKind::planar_beach;
    b.slope = r.uniform(0.005, 0.3);
    b.shoreward_deg = r.uniform(45.0, 135.0);
    b.shoreline = {r.uniform(-0.5 * wx, 0.5 * wx), r.uniform(0.3 * wy, 1.3 * wy)};
  }
  for (int i = r.integer(0, 2); i > 0; --i) {
    houle::Shoal sh;
    sh.center = {r.uniform(-0.5 * wx, 0.5 * wx), r.uniform(0.0, wy)};
    sh.semi_axis_a = r.uniform(2.0, 0.3 * wx);
    sh.semi_axis_b = r.uniform(2.0, 0.3 * wy);
    sh.orientation_deg = r.uniform(0.0, 180.0);
    sh.height = r.uniform(-3.0, 0.9 * b.depth);
    s.floor.shoals.push_back(sh);
  }
  if (r.integer(0, 2) == 0) {
    houle::Bar bar;
    bar.point = {0.0, r.uniform(0.2 * wy, 0.8 * wy)};
    bar.along_deg = r.uniform(-20.0, 20.0);
    bar.half_width = r.uniform(2.0, 20.0);
    bar.height = r.uniform(-1.0, 0.5 * b.depth);
    s.floor.bars.push_back(bar);
  }
  for (int i = r.integer(0, 2); i > 0; --i) {
    // A jetty from the shore side or a detached breakwater, inside the domain.
    houle::Wall w;
    const double x = r.uniform(-0.4 * wx, 0.4 * wx), y0 = r.uniform(0.3 * wy, 0.9 * wy);
    w.points = {{x, y0}, {x + r.uniform(-0.3, 0.3) * wx, y0 + r.uniform(0.05, 0.5) * wy}};
    w.thickness = r.uniform(0.0, 4.0);
    w.reflection = r.uniform(0.0, 1.0);
    s.walls.push_back(w);
  }
  for (int i = r.integer(1, 3); i > 0; --i) {
    houle::WaveTrain t;
    t.direction_deg = r.uniform(30.0, 150.0);
    t.period = r.uniform(1.0, 16.0);
    const double l0 = 9.81 * *t.period * *t.period / (2.0 * 3.141592653589793);
    t.amplitude = r.uniform(0.0, 0.071) * l0 * (r.integer(0, 3) == 0 ? 1.0 : 0.2);  // sometimes at the limit
    t.amplitude = std::min(t.amplitude, 3.0);
    t.phase = r.uniform(-10.0, 10.0);
    t.steepness = r.uniform(0.0, 1.0);
    s.trains.push_back(t);
  }
  s.capillary.amplitude = r.uniform(0.0, 0.03);
  s.dwt.step = r.uniform(0.4, 2.0);
  s.dwt.insertion_distance = r.uniform(1.0, 4.0);
  s.dwt.diffraction_model = houle::DiffractionModel(r.integer(0, 2));
  s.sun.elevation_deg = r.uniform(-10.0, 90.0);
  s.sun.azimuth_deg = r.uniform(0.0, 360.0);
  const double cz = r.uniform(-1.0, 40.0);
  s.camera.position = {r.uniform(-0.5 * wx, 0.5 * wx), r.uniform(-0.2 * wy, 0.5 * wy), cz};
  s.camera.look_at = {r.uniform(-0.5 * wx, 0.5 * wx), r.uniform(0.5 * wy, wy), r.uniform(-5.0, 2.0)};
  s.camera.vertical_fov_deg = r.uniform(10.0, 120.0);
  // An under-floor camera is a validation error, not a property failure: lift it above the floor.
  const double floor_z = -houle::Bathymetry(s.floor).depth(s.camera.position.x, s.camera.position.y);
  s.camera.position.z = std::max(s.camera.position.z, floor_z + 0.5);
  return s;
}

TEST(RandomScenes, FiniteBoundedAndNoEnergyCreated) {
  Random r(20261201);
  houle::test::AmplitudeWorst worst;
  float worst_height = 0.0f, worst_pixel = 0.0f, worst_jump_ratio = 0.0f, edge_ratio = 0.0f, reflected_ratio = 0.0f;
  long skipped = 0;
  std::size_t traced = 0;
  for (int i = 0; i < scene_count; ++i) {
    const houle::Scene scene = random_scene(r);
    const houle::Expected<houle::Scene> valid = houle::validate(scene);
    ASSERT_TRUE(valid) << "scene " << i << ": " << valid.error().field << ": " << valid.error().message;
    const houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 2);
    ASSERT_TRUE(field) << "scene " << i;
    const houle::test::AmplitudeWorst aw = houle::test::amplitude_worst(scene, field.value());
    std::printf("scene %d: %zu trains, %zu walls, %llu rays, %zu samples%s\n", i, scene.trains.size(), scene.walls.size(),
                (unsigned long long)field->stats.rays, aw.samples, field->stats.truncated ? ", truncated" : "");
    EXPECT_TRUE(aw.finite) << "scene " << i;
    EXPECT_LE(aw.breaking, 1.0 + 1e-9) << "scene " << i;
    EXPECT_LE(aw.energy, 1.0 + 1e-9) << "scene " << i;
    worst.breaking = std::max(worst.breaking, aw.breaking);
    worst.energy = std::max(worst.energy, aw.energy);
    worst.caustic = std::max(worst.caustic, aw.caustic);
    worst.samples += aw.samples;
    worst.crossed += aw.crossed;
    for (const houle::WaveRays& t : field->trains) traced += t.analytic ? 0 : 1;

    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), 0.5f);
    ASSERT_TRUE(sea) << "scene " << i;
    houle::SeaSurface s = std::move(sea.value());
    houle::Scene no_reflection = scene;
    no_reflection.dwt.reflection = false;
    const houle::Expected<houle::WaveField> plain_field = houle::trace_wave_field(no_reflection, 2);
    ASSERT_TRUE(plain_field);
    houle::SeaSurface plain = houle::SeaSurface::build(no_reflection, plain_field.value(), 0.5f).value();
    for (double t : {0.0, 7.7, 1e6}) {
      s.set_time(t);
      const houle::Domain& d = scene.domain;
      // Finite and bounded everywhere, in and around the domain; continuous inside covered cells.
      // Known: at the edge of ray coverage the surface oscillates within one cell (in_covered_cell).
      const houle::test::SurfaceSweep sw = houle::test::sweep_surface(s, d.x_min - 10, d.y_min - 10, d.x_max + 10, d.y_max + 10, 0.1f, 40);
      const houle::test::SurfaceSweep covered = houle::test::sweep_surface(s, d.x_min, d.y_min, d.x_max, d.y_max, 0.1f, 40, true);
      EXPECT_TRUE(sw.finite) << "scene " << i << " t " << t;
      EXPECT_LE(sw.worst_height_ratio, 1.0f + 1e-5f) << "scene " << i << " t " << t;
      skipped += covered.skipped;
      if (sw.jump_coarse > 0.0f) edge_ratio = std::max(edge_ratio, sw.jump_fine / sw.jump_coarse);
      worst_height = std::max(worst_height, sw.worst_height_ratio);
      if (covered.jump_coarse > 0.0f) reflected_ratio = std::max(reflected_ratio, covered.jump_fine / covered.jump_coarse);
      // Known defect: with wall reflection the reflected waves' fields are not continuous inside
      // their cells (ratio printed below). Continuity is asserted on the same sea without them.
      plain.set_time(t);
      const houle::test::SurfaceSweep c = houle::test::sweep_surface(plain, d.x_min, d.y_min, d.x_max, d.y_max, 0.1f, 40, true);
      EXPECT_LE(c.jump_fine, 0.5f * c.jump_coarse + 1e-6f) << "scene " << i << " t " << t << " at " << c.worst_x << ", " << c.worst_y;
      if (c.jump_coarse > 0.0f) worst_jump_ratio = std::max(worst_jump_ratio, c.jump_fine / c.jump_coarse);
    }

    houle::Expected<houle::Animation> anim =
        houle::Animation::create(scene, houle::quality_preset(houle::QualityPreset::draft), 48, 27, 2);
    ASSERT_TRUE(anim) << "scene " << i << ": " << anim.error().field << ": " << anim.error().message;
    houle::Framebuffer fb(48, 27);
    for (double t : {0.0, 1e6}) {
      anim->render(t, fb);
      const houle::test::FrameStats f = houle::test::frame_stats(fb);
      EXPECT_TRUE(f.finite) << "scene " << i << " t " << t;
      EXPECT_GE(f.min, 0.0f) << "scene " << i << " t " << t;
      worst_pixel = std::max(worst_pixel, f.max);
    }
  }
  std::printf("worst: %d random scenes, %zu traced trains, %zu samples (%zu behind crossings)\n", scene_count, traced,
              worst.samples, worst.crossed);
  std::printf("worst: 2A/(gamma_b h) %.4f; A/(A0 Ks Kr_max) %.4f overall, %.4f behind crossings\n", worst.breaking,
              worst.energy, worst.caustic);
  std::printf("worst: |h|/bound %.4f; continuity jump ratio (d/4 over d) %.3f in covered cells without reflection, %.3f "
              "with it (%ld probes at coverage edges left out; there the ratio reaches %.3f); brightest pixel %.4g\n",
              worst_height, worst_jump_ratio, reflected_ratio, skipped, edge_ratio, worst_pixel);
  EXPECT_GT(traced, 0u);
  EXPECT_GT(worst.crossed, 0u);  // the sweep reached caustics
}

}  // namespace
