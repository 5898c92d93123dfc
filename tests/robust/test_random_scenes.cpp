// Properties over random valid scenes (seeded, the same scenes on every machine): no NaN or Inf in
// the traced rays, the sea surface or any pixel; amplitude within the breaking limit; no energy
// created at caustics (refraction capped). The worst values over all scenes are printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>

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
  float worst_height = 0.0f, worst_pixel = 0.0f, worst_jump_ratio = 0.0f, edge_ratio = 0.0f;
  long skipped = 0;
  std::size_t traced = 0;
  for (int i = 0; i < scene_count; ++i) {
    houle::Scene scene = random_scene(r);
    scene.wave_model.kind = houle::WaveModelKind(i % 3);  // rays, parabolic, auto in turn
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
    for (double t : {0.0, 7.7, 1e6}) {
      s.set_time(t);
      const houle::Domain& d = scene.domain;
      // Finite and bounded everywhere, in and around the domain; continuous inside covered cells.
      // Known: at the edge of ray coverage the surface oscillates within one cell (in_covered_cell).
      const houle::test::SurfaceSweep sw = houle::test::sweep_surface(s, d.x_min - 10, d.y_min - 10, d.x_max + 10, d.y_max + 10, 0.1f, 40);
      const houle::test::SurfaceSweep c = houle::test::sweep_surface(s, d.x_min, d.y_min, d.x_max, d.y_max, 0.1f, 40, true);
      EXPECT_TRUE(sw.finite) << "scene " << i << " t " << t;
      EXPECT_LE(sw.worst_height_ratio, 1.0f + 1e-5f) << "scene " << i << " t " << t;
      skipped += c.skipped;
      if (sw.jump_coarse > 0.0f) edge_ratio = std::max(edge_ratio, sw.jump_fine / sw.jump_coarse);
      worst_height = std::max(worst_height, sw.worst_height_ratio);
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
  std::printf("worst: |h|/bound %.4f; continuity jump ratio (d/4 over d) %.3f in covered cells (%ld probes at coverage "
              "edges left out; there the ratio reaches %.3f); brightest pixel %.4g\n",
              worst_height, worst_jump_ratio, skipped, edge_ratio, worst_pixel);
  EXPECT_GT(traced, 0u);
  EXPECT_GT(worst.crossed, 0u);  // the sweep reached caustics
}

// Adding an obstacle never changes the field upstream of it by more than what it sends back: for a
// shoal (submerged or an island) nothing; for a wall its reflected wave (alpha) and the diffraction
// tails of its ends (below 0.15 more than 2 L from the wall: |G(s) - 1| < 0.15 for s > 1.9). Random
// floors, trains and obstacles; "upstream" is more than 2 local wavelengths before the obstacle's
// footprint along the train's direction, and inside the domain.
TEST(RandomScenes, AnObstacleChangesNothingUpstreamBeyondWhatItSendsBack) {
  Random r(20261203);
  double worst_shoal = 0.0, worst_wall = 0.0;
  int compared = 0;
  for (int i = 0; i < scene_count; ++i) {
    houle::Scene base;
    const double side = r.uniform(80.0, 200.0);
    base.domain = {0.0, 0.0, side, side};
    base.floor.base.depth = r.uniform(4.0, 30.0);
    if (r.integer(0, 1) == 1) {
      base.floor.base.kind = houle::FloorKind::planar_beach;
      base.floor.base.slope = r.uniform(0.002, 0.02);
      base.floor.base.shoreward_deg = 90.0;
      base.floor.base.shoreline = {0.0, side * r.uniform(1.5, 3.0)};
    }
    houle::WaveTrain t;
    t.direction_deg = r.uniform(60.0, 120.0);
    t.period = r.uniform(2.0, 6.0);
    t.amplitude = 0.1;
    t.steepness = 0.0;
    base.trains = {t};
    base.capillary.amplitude = 0.0;
    base.dwt.analytic_shortcut = false;  // the same tracer with and without the obstacle
    houle::Scene with = base;
    // The obstacle in the domain's upper half; its footprint as a disc (centre, radius).
    const double cx = r.uniform(0.3, 0.7) * side, cy = r.uniform(0.55, 0.8) * side;
    double radius = 0.0, alpha = 0.0;
    const bool wall = r.integer(0, 1) == 1;
    if (wall) {
      const double half = r.uniform(5.0, 0.25 * side), turn = r.uniform(-0.6, 0.6);
      houle::Wall w;
      w.points = {{cx - half * std::cos(turn), cy - half * std::sin(turn)}, {cx + half * std::cos(turn), cy + half * std::sin(turn)}};
      w.thickness = r.uniform(0.0, 3.0);
      w.reflection = alpha = r.uniform(0.0, 1.0);
      with.walls = {w};
      radius = half + w.thickness;
    } else {
      houle::Shoal sh;
      sh.center = {cx, cy};
      sh.semi_axis_a = sh.semi_axis_b = r.uniform(4.0, 0.15 * side);
      sh.height = base.floor.base.depth * r.uniform(0.5, 1.5);  // submerged or an island
      with.floor.shoals = {sh};
      radius = sh.semi_axis_a;
    }
    ASSERT_TRUE(houle::validate(with)) << "scene " << i;
    // Each model against itself (docs/physics.md 10): rays for even scenes, the parabolic model for odd.
    const houle::WaveModelKind kind = i % 2 ? houle::WaveModelKind::parabolic : houle::WaveModelKind::rays;
    base.wave_model.kind = with.wave_model.kind = kind;
    const auto sea_of = [](const houle::Scene& s) {
      const houle::Expected<houle::WaveField> f = houle::trace_wave_field(s, 2);
      EXPECT_TRUE(f);
      return houle::SeaSurface::build(s, f.value(), 0.5f).value();
    };
    const houle::SeaSurface a = sea_of(base), b = sea_of(with);
    const double dx = std::cos(t.direction_deg * 3.141592653589793 / 180.0), dy = std::sin(t.direction_deg * 3.141592653589793 / 180.0);
    double worst = 0.0;
    for (double y = 2.0; y < side - 2.0; y += side / 40.0) {
      for (double x = 2.0; x < side - 2.0; x += side / 40.0) {
        const houle::TrainProbe pa = a.probe(0, float(x), float(y)), pb = b.probe(0, float(x), float(y));
        ASSERT_TRUE(std::isfinite(pb.relative_amplitude) && std::isfinite(pb.phase)) << "scene " << i;
        EXPECT_LE(pb.relative_amplitude, 2.0f * 2.5f) << "scene " << i;  // incident + reflected, caustic cap
        const double before = (cx - x) * dx + (cy - y) * dy - radius;  // m upstream of the footprint
        if (before < 2.0 * pa.wavelength || pa.relative_amplitude <= 0.0f) continue;
        worst = std::max(worst, std::fabs(double(pb.relative_amplitude) - double(pa.relative_amplitude)) /
                                    double(pa.relative_amplitude));
        ++compared;
      }
    }
    std::printf("scene %d (%s): %s, upstream change %.4f of the incident amplitude\n", i, i % 2 ? "parabolic" : "rays",
                wall ? ("wall, alpha " + std::to_string(alpha)).c_str() : "shoal", worst);
    if (wall) {
      EXPECT_LE(worst, alpha + 0.15) << "scene " << i;
      worst_wall = std::max(worst_wall, worst - alpha);
    } else {
      EXPECT_LE(worst, 0.02) << "scene " << i;
      worst_shoal = std::max(worst_shoal, worst);
    }
  }
  std::printf("worst: upstream of a shoal %.4f, of a wall %.4f beyond alpha (%d points)\n", worst_shoal, worst_wall, compared);
  EXPECT_GT(compared, 0);
}

}  // namespace
