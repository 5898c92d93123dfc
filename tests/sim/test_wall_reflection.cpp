// Wall reflection (wave_rays.hpp): the mirror law, the amplitude ratio alpha and phase continuity at
// the wall on the rays, and the standing wave 2 A |cos k d| in front of a rigid wall on the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "houle/sim/dispersion.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
#include "angles.hpp"
#include "ray_walls.hpp"

namespace {

using houle::Scene;
using houle::WaveRays;
using houle_test::pi;

// Flat 10 m, one train from the south, a straight wall across the whole domain (both ends outside
// it: no pierhead, no diffraction) from (-5, y_west) to (205, y_east).
Scene walled_sea(double y_west, double y_east, double alpha, double direction_deg) {
  Scene s;
  s.domain = {0.0, 0.0, 200.0, 100.0};
  s.floor.base.depth = 10.0;
  houle::Wall w;
  w.points = {{-5.0, y_west}, {205.0, y_east}};
  w.thickness = 1.0;
  w.reflection = alpha;
  s.walls = {w};
  houle::WaveTrain t;
  t.direction_deg = direction_deg;
  t.period = 4.0;
  t.amplitude = 0.1;
  t.steepness = 0.0;  // sine profile: the superposition is then exactly linear
  s.trains = {t};
  s.capillary.amplitude = 0.0;
  s.dwt.step = 0.5;
  s.dwt.insertion_distance = 1.5;
  return s;
}

houle::WaveField traced(const Scene& s) {
  auto f = houle::trace_wave_field(s);
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().field + ": " + f.error().message);
  return f.ok() ? std::move(f).value() : houle::WaveField{};
}

// wall_blocks answers first_wall_hit's `hit` without its bisection: the same answer on random chords
// near and through random capsules, zero-length chords (a point in a wall) and grazing ones included.
TEST(WallReflection, WallBlocksIsFirstWallHitsHit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> at(-10.0, 10.0), radius(0.05, 3.0);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<houle::detail::Capsule> walls;
    for (int c = 0; c < 1 + trial % 5; ++c) walls.push_back({at(rng), at(rng), at(rng), at(rng), radius(rng), std::uint32_t(c)});
    const double x0 = at(rng), y0 = at(rng);
    const bool point = trial % 7 == 0;
    const double x1 = point ? x0 : at(rng), y1 = point ? y0 : at(rng);
    const bool blocks = houle::detail::wall_blocks(walls, x0, y0, x1, y1);
    ASSERT_EQ(blocks, houle::detail::first_wall_hit(walls, x0, y0, x1, y1).hit) << "trial " << trial;
    (blocks ? hits : misses)++;
  }
  // A chord that only touches a capsule's surface blocks for neither.
  const std::vector<houle::detail::Capsule> wall = {{0.0, 0.0, 10.0, 0.0, 1.0, 0}};
  EXPECT_FALSE(houle::detail::wall_blocks(wall, -5.0, 1.0, 15.0, 1.0));
  EXPECT_FALSE(houle::detail::first_wall_hit(wall, -5.0, 1.0, 15.0, 1.0).hit);
  EXPECT_GT(hits, 200);
  EXPECT_GT(misses, 200);
}

TEST(WallReflection, MirrorLawAmplitudeRatioAndPhaseContinuity) {
  // An oblique wall (16 degrees) met by an oblique train (70 degrees): incidence 36 degrees off the
  // normal, so the mirror law is checked away from every special angle.
  const double alpha = 0.6;
  const Scene s = walled_sea(20.0, 80.0, alpha, 70.0);
  const houle::WaveField f = traced(s);
  ASSERT_EQ(f.reflections.size(), 1u);
  EXPECT_GT(f.stats.reflected_rays, 50u);
  const WaveRays& in = f.trains[0];
  const WaveRays& re = f.reflections[0].rays;
  // The wall's unit normal towards the sea (south-east of the line).
  const double ex = 210.0, ey = 60.0, el = std::hypot(ex, ey);
  const double nx = ey / el, ny = -ex / el;
  std::map<std::pair<double, double>, std::size_t> hits;  // incident end point -> its sample
  for (std::size_t r = 0; r < in.ray_count(); ++r) {
    if ((in.flags[r] & houle::ray_flag::hit_wall) && in.sample_begin[r + 1] > in.sample_begin[r]) {
      hits[{in.x[in.sample_begin[r + 1] - 1], in.y[in.sample_begin[r + 1] - 1]}] = in.sample_begin[r + 1] - 1;
    }
  }
  const double a_expected = alpha * 0.1 * houle::shoaling_coefficient(houle::linear_wave(in.omega, 10.0).kh);
  double worst_angle = 0.0, worst_ratio = 0.0, worst_phase = 0.0, worst_plane = 0.0;
  std::size_t seeds = 0, samples = 0;
  for (std::size_t r = 0; r < re.ray_count(); ++r) {
    const std::size_t b = re.sample_begin[r], e = re.sample_begin[r + 1];
    if (b == e) continue;
    if (re.parent_a[r] < 0) {
      // A seed: starts exactly where an incident ray ended.
      const auto it = hits.find({re.x[b], re.y[b]});
      ASSERT_NE(it, hits.end()) << "reflected ray " << r << " does not start on an incident hit";
      const std::size_t i = it->second;
      const double dix = std::cos(in.theta[i]), diy = std::sin(in.theta[i]);
      const double drx = std::cos(re.theta[b]), dry = std::sin(re.theta[b]);
      // Angle of incidence (from the normal to -d_i) = angle of reflection (from the normal to d_r),
      // on the other side of the normal.
      const double inc = std::atan2(nx * -diy - ny * -dix, nx * -dix + ny * -diy);
      const double ref = std::atan2(nx * dry - ny * drx, nx * drx + ny * dry);
      worst_angle = std::max(worst_angle, std::fabs(inc + ref));
      EXPECT_NEAR(std::fabs(inc), 36.0 * pi / 180.0, 0.05);  // 90 - 70 + 16 degrees: not a special angle
      worst_ratio = std::max(worst_ratio, std::fabs(re.amplitude[b] / in.amplitude[i] - alpha));
      worst_phase = std::max(worst_phase, std::fabs(re.phase[b] - in.phase[i]));
      ++seeds;
    }
    // A plane wave reflected by a straight wall on a flat bottom is a plane wave: alpha A0 Ks everywhere.
    for (std::size_t q = b; q < e; ++q, ++samples) worst_plane = std::max(worst_plane, std::fabs(re.amplitude[q] / a_expected - 1.0));
  }
  EXPECT_GT(seeds, 50u);
  EXPECT_GT(samples, 10000u);
  EXPECT_LT(worst_angle, 1e-12);   // the mirror construction's rounding
  EXPECT_LT(worst_ratio, 1e-12);
  EXPECT_EQ(worst_phase, 0.0);     // the phase is carried over, not recomputed
  EXPECT_LT(worst_plane, 1e-9);
  std::printf("reflection, alpha %.1f, incidence 36 deg: %zu seeds, %zu samples; |angle in - angle out| %.1e rad, "
              "|A_r/A_i - alpha| %.1e, plane-wave amplitude within %.1e\n",
              alpha, seeds, samples, worst_angle, worst_ratio, worst_plane);
}

TEST(WallReflection, RigidWallMakesAStandingWave) {
  // Normal incidence on a rigid wall along y = 80 (face at y = 79.5): eta = 2 A cos(k d) sin(...),
  // d the distance from the face. Envelope (max |h| over a period) against 2 A |cos k d|.
  const Scene s = walled_sea(80.0, 80.0, 1.0, 90.0);
  const houle::WaveField f = traced(s);
  ASSERT_EQ(f.reflections.size(), 1u);
  auto built = houle::SeaSurface::build(s, f);
  ASSERT_TRUE(built.ok());
  houle::SeaSurface sea = std::move(built).value();
  const double omega = f.trains[0].omega, k = houle::linear_wave(omega, 10.0).k;
  const double a = 0.1 * houle::shoaling_coefficient(k * 10.0);
  const double face = 79.5, wavelength = 2.0 * pi / k;
  double worst = 0.0, node = 0.0, antinode_min = 10.0;
  for (double d = 1.0; d < 40.0; d += 0.37) {
    const float y = float(face - d);
    double envelope = 0.0;
    for (int n = 0; n < 64; ++n) {
      sea.set_time(n * (2.0 * pi / omega) / 64.0);
      for (float x : {60.0f, 100.0f, 140.0f}) {
        float h, gx, gy;
        sea.eval(&x, &y, 1, &h, &gx, &gy);
        envelope = std::max(envelope, double(std::fabs(h)));
      }
    }
    const double expected = 2.0 * a * std::fabs(std::cos(k * d));
    worst = std::max(worst, std::fabs(envelope - expected));
    if (expected < 0.1 * a) node = std::max(node, envelope);
    if (expected > 1.95 * a) antinode_min = std::min(antinode_min, envelope);  // clearly an antinode
  }
  // Tolerance 1 % of 2 A (0.26 % measured): the 64 time samples (cos(pi/64) = 0.9988) and the
  // resampling grid (the phase is bilinear over 0.5 m cells; the tent splat near the wall's face).
  EXPECT_LT(worst, 0.01 * 2.0 * a);
  EXPECT_GT(antinode_min, 1.9 * a);
  std::printf("standing wave before a rigid wall (L = %.2f m): envelope vs 2A|cos kd| worst %.4f m (2A = %.4f m), "
              "antinodes >= %.4f m, nodes <= %.4f m\n",
              wavelength, worst, 2.0 * a, antinode_min, node);
}

TEST(WallReflection, NoReflectionWorkWithoutReflectingWalls) {
  Scene s = walled_sea(80.0, 80.0, 0.0, 90.0);  // absorbing
  EXPECT_FALSE(houle::scene_has_reflecting_walls(s));
  houle::WaveField f = traced(s);
  EXPECT_TRUE(f.reflections.empty());
  EXPECT_EQ(f.stats.reflected_rays, 0u);
  s.walls[0].reflection = 1.0;
  s.dwt.reflection = false;  // switched off
  EXPECT_FALSE(houle::scene_has_reflecting_walls(s));
  f = traced(s);
  EXPECT_TRUE(f.reflections.empty());
  EXPECT_EQ(f.stats.reflected_rays, 0u);
  s.dwt.reflection = true;
  f = traced(s);
  EXPECT_EQ(f.reflections.size(), 1u);
  EXPECT_GT(f.stats.reflected_rays, 0u);
}

TEST(WallReflection, ReflectionInACornerIsFiniteAndBounded) {
  // A rigid V-shaped harbour corner facing the waves (a concave polyline): reflected rays leave the
  // left arm towards 32 degrees from +x (the right one towards 148), cross each other, meet the other
  // arm (where they end: one order of reflection) or leave the domain. Finite, bounded by the
  // caustic cap, every ray ended.
  Scene s = walled_sea(0.0, 0.0, 1.0, 90.0);
  s.walls[0].points = {{45.0, -5.0}, {100.0, 95.0}, {155.0, -5.0}};  // arms 61 degrees from the x axis
  const houle::WaveField f = traced(s);
  ASSERT_EQ(f.reflections.size(), 1u);
  const WaveRays& re = f.reflections[0].rays;
  const double cap = s.dwt.max_refraction_coefficient * 0.1 * houle::shoaling_coefficient(houle::linear_wave(re.omega, 10.0).kh);
  std::size_t on_wall = 0;
  for (std::size_t r = 0; r < re.ray_count(); ++r) {
    ASSERT_TRUE(re.flags[r] & houle::ray_flag::dead);
    on_wall += (re.flags[r] & houle::ray_flag::hit_wall) ? 1 : 0;
    for (std::size_t i = re.sample_begin[r]; i < re.sample_begin[r + 1]; ++i) {
      ASSERT_TRUE(std::isfinite(re.x[i]) && std::isfinite(re.y[i]) && std::isfinite(re.amplitude[i]) && std::isfinite(re.phase[i]));
      ASSERT_LE(re.amplitude[i], cap * (1.0 + 1e-12));
    }
  }
  EXPECT_GT(on_wall, 0u);  // some meet the other arm
  auto built = houle::SeaSurface::build(s, f);
  ASSERT_TRUE(built.ok());
  EXPECT_LE(built->height_bound(), 2.0 * cap + 1e-6);
}

}  // namespace
