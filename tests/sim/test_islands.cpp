// Land that rises through the surface inside the domain (docs/physics.md 2.6): an island, a shoal
// just under the surface and an island from a height map change nothing upstream of them. The
// oracle is the same scene without the obstacle, whose train is the analytic plane wave.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

// A flat 8 m sea, 200 m x 200 m, one train (4 s, 0.2 m, towards +y: L = 24.2 m).
houle::Scene open_sea() {
  houle::Scene s;
  s.domain = {0.0, 0.0, 200.0, 200.0};
  s.floor.base.depth = 8.0;
  houle::WaveTrain t;
  t.direction_deg = 90.0;
  t.period = 4.0;
  t.amplitude = 0.2;
  s.trains = {t};
  s.capillary.amplitude = 0.0;
  return s;
}

// A round shoal of radius 10 m at (100, 150) rising `height` m from the 8 m floor.
houle::Scene with_shoal(double height) {
  houle::Scene s = open_sea();
  houle::Shoal sh;
  sh.center = {100.0, 150.0};
  sh.semi_axis_a = sh.semi_axis_b = 10.0;
  sh.height = height;
  s.floor.shoals = {sh};
  return s;
}

// The same island sampled every metre: a cone of radius 12 m whose top stands 1 m out of the water.
houle::Scene with_height_map_island() {
  houle::Scene s = open_sea();
  houle::HeightMap m;
  m.nx = m.ny = 201;
  m.cell = 1.0;
  m.depth.resize(std::size_t(m.nx) * m.ny);
  for (std::uint32_t j = 0; j < m.ny; ++j) {
    for (std::uint32_t i = 0; i < m.nx; ++i) {
      const double r = std::hypot(double(i) - 100.0, double(j) - 150.0);
      m.depth[std::size_t(j) * m.nx + i] = float(r < 12.0 ? -1.0 + 9.0 * r / 12.0 : 8.0);
    }
  }
  s.floor.height_map = std::move(m);
  return s;
}

// Traces `scene` and compares its train, upstream of y = y_max, with the open sea's, point by point.
void expect_unchanged_upstream(const houle::Scene& scene, double y_max, const char* name) {
  auto field = houle::trace_wave_field(scene);
  ASSERT_TRUE(field.ok()) << field.error().message;
  EXPECT_FALSE(field->stats.truncated) << name << ": the trace hit a cap";
  auto surface = houle::SeaSurface::build(scene, field.value());
  ASSERT_TRUE(surface.ok()) << surface.error().message;
  const houle::Scene reference_scene = open_sea();
  auto reference_field = houle::trace_wave_field(reference_scene);
  ASSERT_TRUE(reference_field.ok());
  auto reference = houle::SeaSurface::build(reference_scene, reference_field.value());
  ASSERT_TRUE(reference.ok());
  double worst_a = 0.0, worst_dir = 0.0;
  int points = 0;
  for (double y = 5.0; y <= y_max; y += 5.0) {
    for (double x = 10.0; x <= 190.0; x += 5.0) {
      const houle::TrainProbe p = surface->probe(0, float(x), float(y));
      const houle::TrainProbe q = reference->probe(0, float(x), float(y));
      ASSERT_GT(q.amplitude, 0.0f);
      worst_a = std::max(worst_a, std::fabs(double(p.amplitude) / double(q.amplitude) - 1.0));
      worst_dir = std::max(worst_dir, std::fabs(std::remainder(double(p.direction_deg) - double(q.direction_deg), 360.0)));
      ++points;
    }
  }
  std::printf("%s: %d points upstream (y <= %.0f m): amplitude within %.4f, direction within %.3f deg; %llu rays, "
              "%llu turned back\n", name, points, y_max, worst_a, worst_dir, (unsigned long long)field->stats.rays,
              (unsigned long long)field->stats.turned_back);
  EXPECT_LE(worst_a, 0.02) << name;
  EXPECT_LE(worst_dir, 1.0) << name;
}

// Upstream means farther than 2 L (48 m) from the obstacle's rim (y = 140 m).
constexpr double upstream_y = 140.0 - 2.0 * 24.2;

TEST(Islands, AnIslandChangesNothingUpstream) { expect_unchanged_upstream(with_shoal(9.0), upstream_y, "island"); }

TEST(Islands, AShoalJustUnderTheSurfaceChangesNothingUpstream) {
  expect_unchanged_upstream(with_shoal(7.9), upstream_y, "shoal 0.1 m under the surface");
}

TEST(Islands, AnIslandFromAHeightMapChangesNothingUpstream) {
  expect_unchanged_upstream(with_height_map_island(), 138.0 - 2.0 * 24.2, "height-map island");
}

// Rays that refraction turned round end where they turned: the island costs a few hundred rays, not
// the tens of thousands that filled the domain with back-scattered rays before.
TEST(Islands, RaysRoundAnIslandStayFewAndEndWhenTheyTurnBack) {
  auto field = houle::trace_wave_field(with_shoal(9.0));
  ASSERT_TRUE(field.ok());
  const houle::WaveRays& w = field->trains[0];
  EXPECT_LT(w.ray_count(), 2000u);
  EXPECT_GT(field->stats.turned_back, 0u);
  for (std::size_t r = 0; r < w.ray_count(); ++r) {
    // Every on-grid sample travels with the train (a ray's last, off-grid sample may have turned).
    for (std::size_t s = w.sample_begin[r]; s < w.sample_begin[r + 1]; ++s) {
      if (w.sample_flags[s] & houle::sample_flag::off_grid) continue;
      ASSERT_GE(std::sin(w.theta[s]), -1e-9) << "ray " << r << " sample " << s;
    }
  }
}

// A breakwater in the island's lee reflects the wave back onto it. Reflected rays are held to the
// direction they left the wall in, as incident rays are to their train's: traced on round the island,
// they orbited it and insertion filled the gaps until the sample cap (21,456 reflected rays in a
// user's harbour scene, which then refused to render).
TEST(Islands, ReflectedRaysRoundAnIslandEndWhenTheyTurnBack) {
  houle::Scene s = with_shoal(9.0);
  houle::Wall w;
  w.points = {{70.0, 185.0}, {130.0, 185.0}};
  w.thickness = 2.0;
  s.walls = {w};
  auto field = houle::trace_wave_field(s);
  ASSERT_TRUE(field.ok()) << field.error().message;
  EXPECT_FALSE(field->stats.truncated);
  ASSERT_EQ(field->reflections.size(), 1u);
  const houle::WaveRays& r = field->reflections[0].rays;
  std::printf("reflected wave: %zu rays, %zu samples\n", r.ray_count(), r.sample_count());
  EXPECT_LT(r.ray_count(), 4000u);  // 2,250 today
  std::size_t checked = 0;
  for (std::size_t q = 0; q < r.ray_count(); ++q) {
    const std::size_t first = r.sample_begin[q];
    for (std::size_t k = first; k < r.sample_begin[q + 1]; ++k) {
      if (r.sample_flags[k] & houle::sample_flag::off_grid) continue;
      ASSERT_GE(std::cos(r.theta[k] - r.theta[first]), -1e-9) << "reflected ray " << q << " sample " << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000u);
}

}  // namespace
