// The parabolic model (docs/physics.md 10) against the laboratory experiment of Berkhoff, Booy &
// Radder (1982) and against linear theory on a plane beach (Snell and shoaling). The semi-infinite
// breakwater against Sommerfeld is in test_coastal_oracles.cpp with the rays' cases.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"
#include "angles.hpp"
#include "beach_scene.hpp"
#include "berkhoff_shoal.hpp"
#include "parabolic_model.hpp"

namespace {

using houle_test::pi;

struct SectionErrors {
  std::map<int, std::pair<double, int>> per;  // sum of squares, count
  double all = 0.0;
  int count = 0;
  void add(int section, double e) {
    per[section].first += e * e;
    per[section].second += 1;
    all += e * e;
    ++count;
  }
  double rms() const { return std::sqrt(all / count); }
  double rms(int section) const { return std::sqrt(per.at(section).first / per.at(section).second); }
};

/// H / H0 against the 208 measurements, as `houle probe` reads the sea (realtime's 0.5 m cells).
SectionErrors berkhoff_errors(houle::WaveModelKind kind) {
  const houle::Scene scene = houle_test::berkhoff_scene(kind);
  auto field = houle::trace_wave_field(scene, 1);
  EXPECT_TRUE(field.ok());
  auto sea = houle::SeaSurface::build(scene, *field, 0.5f);
  EXPECT_TRUE(sea.ok());
  SectionErrors e;
  for (const houle_test::BerkhoffPoint& p : houle_test::berkhoff_measurements(HOULE_TEST_DATA_DIR)) {
    const double relative = sea->probe(0, float(p.x), float(p.y)).amplitude / houle_test::berkhoff_amplitude;
    e.add(p.section, relative - p.relative);
  }
  std::printf("Berkhoff shoal, %s: RMS of H/H0 %.3f over %d points; per section",
              kind == houle::WaveModelKind::rays ? "rays" : kind == houle::WaveModelKind::parabolic ? "parabolic" : "auto",
              e.rms(), e.count);
  for (const auto& [section, sums] : e.per) std::printf(" %d: %.3f", section, e.rms(section));
  std::printf("\n");
  return e;
}

// The bounds: RMS over all sections at most 0.15, no section above 0.25, with the parabolic
// model and with auto (which picks it over a height map). Rays cannot: behind the focus their
// caustic arms sit where the measured minima are (docs/physics.md 10.5).
TEST(ParabolicModel, BerkhoffShoalWithinTheMeasurements) {
  for (const houle::WaveModelKind kind : {houle::WaveModelKind::parabolic, houle::WaveModelKind::automatic}) {
    const SectionErrors e = berkhoff_errors(kind);
    EXPECT_EQ(e.count, 208);
    EXPECT_LE(e.rms(), 0.15);
    for (const auto& [section, sums] : e.per) EXPECT_LE(e.rms(section), 0.25) << "section " << section;
  }
  EXPECT_GT(berkhoff_errors(houle::WaveModelKind::rays).rms(), 0.3);
}

// A plane beach (contours along x, depth 2-10 m over the domain), a train 30 deg off the shore's
// normal: linear theory's Snell (sin a / C conserved) and shoaling with refraction (A = A0 Ks Kr),
// within 1 % (measured 0.69 % and 0.35 %: docs/physics.md 10.4). Amplitude dispersion is off: the
// oracle is linear.
TEST(ParabolicModel, PlaneBeachFollowsSnellAndShoaling) {
  houle::Scene s = houle_test::beach_scene(60.0, 0.4);
  s.trains[0].steepness = 0.0;
  s.capillary.amplitude = 0.0;
  s.wave_model.kind = houle::WaveModelKind::parabolic;
  s.wave_model.amplitude_dispersion = false;
  const houle::Bathymetry floor(s.floor);
  auto field = houle::trace_wave_field(s, 1);
  ASSERT_TRUE(field.ok());
  auto sea = houle::SeaSurface::build(s, *field, 2.0f);
  ASSERT_TRUE(sea.ok());
  EXPECT_EQ(sea->trains()[0].model, houle::WaveModelKind::parabolic);
  // The march itself, for the wave's direction (the phase gradient of its field).
  const houle::WaveTrain& t = s.trains[0];
  const double omega = houle::train_omega(t);
  const houle::LinearWave entry = houle::linear_wave(omega, floor.depth(400.0, 0.0));  // the 10 m south of the domain
  const auto marched = houle::detail::march_parabolic(s, floor, houle::detail::parabolic_train(s, floor, 0));
  ASSERT_TRUE(marched.ok());
  const auto eta = [&](double x, double y) { return marched->relative(x, y, 0.0, [](double, double) { return false; }).value_or(0.0); };
  const double q0 = std::sin(30.0 * pi / 180.0) / entry.c;  // sin a / C at the entry depth
  double worst_snell = 0.0, worst_amplitude = 0.0;
  int checked = 0;
  for (double y = 20.0; y <= 380.0; y += 20.0) {
    // Where the wave at (x, y) came into the domain through its southern edge, along Snell's ray
    // (dx/dy = tan a); points whose wave came in through the western edge, across the floor the march
    // assumes outside the domain (its nearest point's), are not this oracle's (docs/physics.md 10.4).
    double x_entry = 0.0;
    for (double yy = 0.0; yy < y; yy += 1.0) {
      const double sin_a = q0 * houle::linear_wave(omega, floor.depth(0.0, yy + 0.5)).c;
      x_entry -= sin_a / std::sqrt(1.0 - sin_a * sin_a);
    }
    for (double x = 250.0; x <= 750.0; x += 50.0) {
      if (x + x_entry < 100.0) continue;
      const double h = floor.depth(x, y);
      const houle::LinearWave w = houle::linear_wave(omega, h);
      // Expected: Snell's angle and A0 Ks Kr, Kr relative to the entry's 30 deg.
      const double sin_a = q0 * w.c, cos_a = std::sqrt(1.0 - sin_a * sin_a);
      const double expected = t.amplitude * houle::shoaling_coefficient(w.kh) * std::sqrt(std::cos(30.0 * pi / 180.0) / cos_a);
      worst_amplitude = std::max(worst_amplitude, std::fabs(sea->probe(0, float(x), float(y)).amplitude / expected - 1.0));
      // The direction of travel as a row of gauges would measure it: the phase difference across half
      // a wavelength, along x and along y.
      const double d = 0.25 * 2.0 * pi / w.k;
      const double gx = std::arg(eta(x + d, y) * std::conj(eta(x - d, y))) / (2.0 * d);
      const double gy = std::arg(eta(x, y + d) * std::conj(eta(x, y - d))) / (2.0 * d);
      const double measured_sin = gx / std::hypot(gx, gy);  // the angle from the contours' normal (+y)
      worst_snell = std::max(worst_snell, std::fabs(measured_sin / w.c / q0 - 1.0));
      ++checked;
    }
  }
  std::printf("plane beach, parabolic: %d points, sin a / C conserved to %.2e, A vs A0 Ks Kr to %.2e\n", checked,
              worst_snell, worst_amplitude);
  EXPECT_LT(worst_snell, 0.01);
  EXPECT_LT(worst_amplitude, 0.01);
}

}  // namespace

// The largest domain validate accepts, with short waves over a shoal: the march stays within its node
// budget (coarser, and saying so: the resolved wavelength grows), and its field is finite.
TEST(ParabolicModel, AHugeDomainStaysWithinItsNodeBudget) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 4000.0, 4000.0};
  s.floor.base.depth = 15.0;
  s.floor.shoals.push_back(houle::Shoal{{2000.0, 2000.0}, 300.0, 200.0, 30.0, 10.0});
  houle::WaveTrain t;
  t.direction_deg = 75.0;
  t.period = 3.0;
  t.amplitude = 0.3;
  s.trains = {t};
  const houle::Bathymetry floor(s.floor);
  const houle::detail::ParabolicTrain pt = houle::detail::parabolic_train(s, floor, 0);
  const std::uint64_t nodes = houle::detail::parabolic_nodes(s, floor, pt);
  EXPECT_LE(nodes, houle::detail::max_parabolic_nodes);
  const auto f = houle::detail::march_parabolic(s, floor, pt);
  ASSERT_TRUE(f.ok());
  EXPECT_LE(std::uint64_t(f->rows()) * f->columns, nodes);
  // Coarsened: at full resolution it would be the wavelength over the shoal's top, 5 m deep.
  EXPECT_GT(f->resolved_wavelength, 2.0 * houle_test::pi / houle::linear_wave(houle::train_omega(t), 5.0).k);
  bool finite = true;
  double largest = 0.0;
  for (const std::complex<float>& v : f->eta) {
    finite = finite && std::isfinite(v.real()) && std::isfinite(v.imag());
    largest = std::max(largest, double(std::abs(v)));
  }
  EXPECT_TRUE(finite);
  EXPECT_LT(largest, 0.5 * s.dwt.breaker_index * 15.0);
  std::printf("4 km domain, 3 s waves: %zu x %u march nodes (budget %llu), wavelengths down to %.2f m resolved\n",
              f->rows(), f->columns, static_cast<unsigned long long>(houle::detail::max_parabolic_nodes), f->resolved_wavelength);
}

// What the build's estimate counts of a march (sim/src/build_cost.cpp): its nodes, from the depths,
// and its wall tests. A scene the scene fuzzer found had walls of 5,300 segments across a thin domain:
// the march tested them for 11 s of CPU while the estimate, which did not count them, said 3 s.
TEST(ParabolicModel, TheBuildEstimateCountsTheMarchsNodesAndWallTests) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 300.0, 120.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 12.0;
  s.floor.base.slope = 0.1;
  s.floor.base.shoreline = {0.0, 115.0};
  s.floor.shoals.push_back(houle::Shoal{{150.0, 50.0}, 20.0, 12.0, 0.0, 3.0});
  houle::WaveTrain t;
  t.direction_deg = 80.0;
  t.period = 4.0;
  t.amplitude = 0.2;
  s.trains = {t};
  // A breakwater of 400 short segments zig-zagging along y = 60 with gaps of open water between
  // its pieces, and a long diagonal wall.
  for (int piece = 0; piece < 4; ++piece) {
    houle::Wall w;
    w.thickness = 1.0;
    for (int i = 0; i <= 100; ++i) {
      w.points.push_back({20.0 + 70.0 * piece + 0.4 * i, 60.0 + (i % 2 ? 1.5 : -1.5)});
    }
    s.walls.push_back(w);
  }
  s.walls.push_back(houle::Wall{{{250.0, 0.0}, {300.0, 40.0}}});
  const houle::Bathymetry floor(s.floor);
  const houle::detail::ParabolicTrain pt = houle::detail::parabolic_train(s, floor, 0);
  const auto f = houle::detail::march_parabolic(s, floor, pt);
  ASSERT_TRUE(f.ok());
  const double nodes = double(f->rows()) * f->columns;
  const houle::detail::ParabolicWork work = houle::detail::parabolic_work(s, floor, pt);
  const double expected = double(work.nodes), tests = double(work.wall_tests);
  std::printf("march: %.0f nodes, %.0f expected (bound %llu); %llu wall tests, %.0f bounded\n", nodes, expected,
              static_cast<unsigned long long>(houle::detail::parabolic_nodes(s, floor, pt)),
              static_cast<unsigned long long>(f->wall_tests), tests);
  EXPECT_GT(expected, 0.7 * nodes);
  EXPECT_LT(expected, 1.5 * nodes);
  EXPECT_GE(tests, double(f->wall_tests));
  EXPECT_LT(tests, 10.0 * double(f->wall_tests));
}

// A rough floor (24 each of shoals, bars and channels on a 200 m beach): rays split round every
// feature, and insertion went on to dwt.max_rays (32,768 rays from 257), where the trace stopped and
// the default on_cap = "error" refused a scene that validated. Where the march carries the field the
// rays only seed the carrier: insertion stops at its budget, and a cap is no truncation.
TEST(ParabolicModel, RaysOverARoughFloorStayWithinTheirBudget) {
  houle::Scene s;
  s.domain = {0.0, 0.0, 200.0, 200.0};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 15.0;
  s.floor.base.slope = 0.02;
  s.floor.base.shoreline = {0.0, 190.0};
  std::uint64_t state = 1;
  const auto uniform = [&](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * double(state >> 11) * 0x1p-53;
  };
  for (int i = 0; i < 24; ++i) {
    s.floor.shoals.push_back({{uniform(0, 200), uniform(0, 160)}, uniform(2, 20), uniform(2, 20), 0.0, uniform(-2, 2)});
    s.floor.bars.push_back({{uniform(0, 200), uniform(0, 160)}, uniform(-30, 30), uniform(1, 5), uniform(-0.5, 0.5)});
    s.floor.channels.push_back({{uniform(0, 200), uniform(0, 160)}, {uniform(0, 200), uniform(0, 160)}, uniform(1, 5), uniform(-1, 1)});
  }
  houle::WaveTrain t;
  t.direction_deg = 70.0;
  t.period = 4.0;
  t.amplitude = 0.3;
  s.trains = {t};
  ASSERT_EQ(houle::scene_wave_model(s).kind, houle::WaveModelKind::parabolic);
  houle::DwtStats stats;
  auto rays = houle::trace_train(s, 0, s.dwt, &stats, 1);
  ASSERT_TRUE(rays.ok());
  std::printf("rough floor: %llu rays from %llu initial, %llu samples\n", (unsigned long long)stats.rays,
              (unsigned long long)stats.initial_rays, (unsigned long long)stats.samples);
  EXPECT_LE(stats.rays, 8 * stats.initial_rays);
  EXPECT_FALSE(stats.truncated);
  auto field = houle::trace_wave_field(s, 1);
  ASSERT_TRUE(field.ok()) << field.error().message;
  auto sea = houle::SeaSurface::build(s, *field, 1.0f);
  ASSERT_TRUE(sea.ok());
  // The sea among the features has its wave (the march's), though the rays stopped refining.
  EXPECT_GT(sea->probe(0, 100.0f, 40.0f).amplitude, 0.1f);  // 0.15 m; 0.3 offshore
}
