#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "houle/sim/bathymetry.hpp"
#include "houle/sim/diffraction.hpp"
#include "houle/sim/dispersion.hpp"
#include "houle/sim/sea_surface.hpp"
#include "houle/sim/wave_rays.hpp"

namespace {

houle::Scene deep_sea() {
  houle::Scene s;
  s.domain = {0.0, 0.0, 100.0, 100.0};
  s.floor.base.depth = 200.0;
  houle::WaveTrain t;
  t.direction_deg = 60.0;
  t.period = 5.0;
  t.amplitude = 0.4;
  t.steepness = 0.5;
  t.phase = 0.3;
  s.trains = {t};
  s.capillary.amplitude = 0.0;
  return s;
}

// deep_sea()'s train on a 1:20 beach: 12 m deep offshore, the shoreline at y = 150 m.
houle::Scene beach() {
  houle::Scene s = deep_sea();
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 12.0;
  s.floor.base.slope = 0.05;
  s.floor.base.shoreline = {0.0, 150.0};
  return s;
}

houle::SeaSurface build(const houle::Scene& scene) {
  auto field = houle::trace_wave_field(scene);
  EXPECT_TRUE(field.ok());
  auto surface = houle::SeaSurface::build(scene, field.value());
  EXPECT_TRUE(surface.ok());
  return std::move(surface.value());
}

// Central differences of the evaluated height against the evaluated gradient.
double worst_gradient_error(const houle::SeaSurface& s, double x0, double x1, double y0, double y1) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ux{float(x0), float(x1)}, uy{float(y0), float(y1)};
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const float x = ux(rng), y = uy(rng), e = 1e-2f;
    const float xs[5] = {x, x + e, x - e, x, x};
    const float ys[5] = {y, y, y, y + e, y - e};
    float h[5], gx[5], gy[5];
    s.eval(xs, ys, 5, h, gx, gy);
    worst = std::max({worst, double(std::fabs((h[1] - h[2]) / (2 * e) - gx[0])), double(std::fabs((h[3] - h[4]) / (2 * e) - gy[0]))});
  }
  return worst;
}

TEST(SeaSurface, DeepFlatSeaIsTheAnalyticTrochoid) {
  const houle::Scene scene = deep_sea();
  ASSERT_FALSE(houle::train_needs_rays(scene, 0));
  houle::SeaSurface s = build(scene);
  const double t = 7.5;
  s.set_time(t);
  const double omega = 2.0 * std::numbers::pi / 5.0, k = omega * omega / 9.81;
  const double dx = std::cos(std::numbers::pi / 3), dy = std::sin(std::numbers::pi / 3);
  for (float x = -50.0f; x < 150.0f; x += 7.3f) {
    const float y = 0.37f * x;
    float h, gx, gy;
    s.eval(&x, &y, 1, &h, &gx, &gy);
    // Phase relative to the upstream corner (0, 0): k d.p - (omega t - phase).
    const double theta = k * (dx * x + dy * y) - std::remainder(omega * t - 0.3, 2 * std::numbers::pi);
    const double qka = 0.5 * k * 0.4;
    EXPECT_NEAR(h, 0.4 * std::sin(theta - qka * std::cos(theta)), 2e-5);
  }
  EXPECT_LT(worst_gradient_error(s, -50, 150, -50, 150), 2e-3);
  EXPECT_NEAR(s.height_bound(), 0.4f, 1e-6f);
}

TEST(SeaSurface, TracedBeachIsContinuousAndBounded) {
  houle::Scene scene = beach();
  scene.trains[0].direction_deg = 80.0;
  scene.dwt.step = 0.5;
  scene.dwt.insertion_distance = 1.5;
  ASSERT_TRUE(houle::train_needs_rays(scene, 0));
  houle::SeaSurface s = build(scene);
  s.set_time(3.0);
  // Inside the grid the bilinear fields make the gradient approximate, not exact: tolerance from
  // the interpolation of k over a 0.5 m cell.
  EXPECT_LT(worst_gradient_error(s, 5, 95, 5, 60), 0.05);
  // No seam where the upstream far field meets the grid at the domain's southern edge.
  for (float x = 10.0f; x < 90.0f; x += 3.1f) {
    const float xs[2] = {x, x}, ys[2] = {-0.01f, 0.01f};
    float h[2], gx[2], gy[2];
    s.eval(xs, ys, 2, h, gx, gy);
    EXPECT_NEAR(h[0], h[1], 0.03) << "x = " << x;
  }
  // Everything finite, and within the bound.
  for (float y = -20.0f; y < 120.0f; y += 0.77f) {
    for (float x = -20.0f; x < 120.0f; x += 1.3f) {
      float h, gx, gy;
      s.eval(&x, &y, 1, &h, &gx, &gy);
      ASSERT_TRUE(std::isfinite(h) && std::isfinite(gx) && std::isfinite(gy));
      ASSERT_LE(std::fabs(h), s.height_bound() + 1e-5f);
    }
  }
}

TEST(SeaSurface, NodesAHairUnderWaterKeepAFiniteWavenumber) {
  // A beach whose waterline runs through a row of grid nodes leaves some of them a rounding error
  // under water (1e-16 m): their wavenumber was sqrt(k0 / h), 1e7 rad/m, the carrier's phase jumped
  // by 1e7 rad across a cell and the height left its bound (found by fuzz_scene_build). They take
  // the shallowest depth the sea models (1 mm), as the breaking cap does: k at most that depth's.
  houle::Scene scene = beach();
  scene.floor.base.depth = 8.0;
  scene.floor.base.slope = 0.1;
  scene.floor.base.shoreline = {5.0, 100.0};
  scene.trains[0].period = 6.0;
  scene.trains[0].amplitude = 0.8;
  scene.walls = {houle::Wall{{{0.0, 60.0}, {50.0, 60.0}}}};
  auto field = houle::trace_wave_field(scene);
  ASSERT_TRUE(field.ok());
  auto built = houle::SeaSurface::build(scene, field.value(), 100.0f / 64.0f);
  ASSERT_TRUE(built.ok());
  houle::SeaSurface& sea = built.value();
  const double omega = 2.0 * std::numbers::pi / 6.0, k_max = omega / std::sqrt(9.81 * 1e-3);
  const houle::Bathymetry floor(scene.floor);
  int hair = 0;
  for (float y = 0.0f; y <= 100.0f; y += 100.0f / 64.0f) {
    for (float x = 0.0f; x <= 100.0f; x += 100.0f / 64.0f) {
      const double depth = floor.depth(x, y);
      if (depth > 0.0 && depth < 1e-3) ++hair;
      const houle::TrainProbe p = sea.probe(0, x, y);
      if (p.wavelength > 0.0f) {
        ASSERT_GT(p.wavelength, 0.99 * 2.0 * std::numbers::pi / k_max) << x << ", " << y;
      }
    }
  }
  EXPECT_GT(hair, 0) << "the case needs nodes a hair under water";
  for (double t : {0.0, 1e6}) {
    sea.set_time(t);
    for (float y = 90.0f; y <= 100.0f; y += 0.3f) {
      for (float x = 0.0f; x <= 10.0f; x += 0.3f) {
        float h, gx, gy;
        sea.eval(&x, &y, 1, &h, &gx, &gy);
        ASSERT_LE(std::fabs(h), sea.height_bound() * 1.001f) << x << ", " << y << " at " << t << " s";
      }
    }
  }
}

TEST(SeaSurface, TheProbesPartsAreTheWaveAsItIsHereUpToTheWaterline) {
  // On a bare beach the whole wave is incident: the probe's incident part must be its amplitude,
  // in the surf zone and between the rays' end and the waterline, where the wave is carried on.
  // Before, the parts there were 0.
  houle::Scene scene = beach();
  scene.domain.y_max = 160.0;
  auto field = houle::trace_wave_field(scene);
  ASSERT_TRUE(field.ok());
  auto built = houle::SeaSurface::build(scene, field.value(), 0.5f, houle::SeaParts::keep);
  ASSERT_TRUE(built.ok());
  const houle::SeaSurface& sea = built.value();
  int surf = 0, carried = 0;
  for (float y = 60.0f; y < 150.0f; y += 0.25f) {
    const houle::TrainProbe p = sea.probe(0, 50.0f, y);
    if (p.amplitude <= 0.0f) continue;
    // The parts interpolate magnitudes, the amplitude the complex B (whose phase turns a little
    // across a cell): equal to 1e-3 here.
    EXPECT_NEAR(p.incident, p.amplitude, 1e-3f * p.amplitude) << "y " << y;
    EXPECT_EQ(p.diffracted, 0.0f);
    EXPECT_EQ(p.reflected, 0.0f);
    const double depth = 0.05 * (150.0 - y);
    if (depth < field->trains[0].min_depth) {
      ++carried;
    } else if (p.amplitude > 0.9f * 0.39f * float(depth)) {
      ++surf;  // held at gamma_b h / 2 = 0.39 h: breaking
    }
  }
  EXPECT_GT(surf, 10);
  EXPECT_GT(carried, 0);
}

TEST(SeaSurface, ProbeReportsTheDiffractionCoefficient) {
  // The paper's Fig. 4 (rigid wall from (0, 50) to the pierhead (50, 50), waves from the south):
  // the probe's K' against the exact Sommerfeld coefficient in the lee, on the shadow line and on
  // the lit side beyond the tip, and A = A0 Ks K' on a flat bottom. (In front of this 1 m thick wall
  // the reflected wave starts half a metre before the thin wall of the exact solution:
  // test_coastal_oracles.cpp measures that side with a thin wall.) Tolerance 0.005: the diffracted wave is exact at
  // the nodes; the rest is bilinear interpolation between them.
  const houle::Scene scene = houle::paper_fig4();
  houle::SeaSurface s = build(scene);
  const double omega = 2.0 * std::numbers::pi / 2.5;
  const houle::LinearWave lw = houle::linear_wave(omega, 10.0);
  const auto frame = houle::make_breakwater_frame(houle::Breakwater{50.0, 50.0, -1.0, 0.0}, 0.0, 1.0, 2.0 * std::numbers::pi / lw.k);
  ASSERT_TRUE(frame.ok());
  double worst = 0.0, worst_amplitude = 0.0;
  for (const auto& [x, y] : {std::pair{25.0, 75.0}, {40.0, 90.0}, {10.0, 60.0}, {50.0, 80.0}, {45.0, 70.0}, {60.0, 85.0}, {90.0, 90.0},
                              {70.0, 40.0}}) {
    const houle::TrainProbe p = s.probe(0, float(x), float(y));
    const houle::BreakwaterPolar polar = houle::breakwater_polar(frame.value(), x, y);
    const auto exact = houle::diffraction(houle::DiffractionModel::exact, polar.r_over_L, polar.theta, polar.theta0, 1.0);
    ASSERT_TRUE(exact.ok());
    worst = std::max(worst, std::fabs(double(p.diffraction) - exact->K));
    worst_amplitude = std::max(worst_amplitude, std::fabs(double(p.amplitude) - 0.15 * houle::shoaling_coefficient(lw.kh) * double(p.diffraction)));
    std::printf("(%g, %g): probe K' %.4f, exact %.4f\n", x, y, p.diffraction, exact->K);
  }
  EXPECT_LT(worst, 0.005);
  EXPECT_LT(worst_amplitude, 1e-3);
  // Outside the grid the nearest edge point's wave goes on (here the corner's, where the wall's
  // reflection has left the domain); for a train without diffraction K' = 1.
  EXPECT_EQ(s.probe(0, -10.0f, -10.0f).diffraction, s.probe(0, 0.0f, 0.0f).diffraction);
  EXPECT_EQ(s.probe(0, -10.0f, -10.0f).amplitude, s.probe(0, 0.0f, 0.0f).amplitude);
  const houle::SeaSurface deep = build(deep_sea());
  EXPECT_EQ(deep.probe(0, 50.0f, 50.0f).diffraction, 1.0f);
  // The reflected wave is part of the train: one field per scene train.
  EXPECT_EQ(s.trains().size(), scene.trains.size());
  // Its parts, kept for the probe: in the lee only the diffracted wave; in front of the wall the
  // incident and the reflected wave (alpha = 1), each A0 Ks, and a diffracted tail; without
  // SeaParts::keep none.
  const houle::WaveField field = houle::trace_wave_field(scene).value();
  const houle::SeaSurface parts = houle::SeaSurface::build(scene, field, 0.5f, houle::SeaParts::keep).value();
  const double a = 0.15 * houle::shoaling_coefficient(lw.kh);
  const houle::TrainProbe lee = parts.probe(0, 25.0f, 75.0f), front = parts.probe(0, 25.0f, 30.0f);
  EXPECT_EQ(lee.incident, 0.0f);
  EXPECT_EQ(lee.reflected, 0.0f);
  EXPECT_NEAR(lee.diffracted, lee.amplitude, 1e-6);
  EXPECT_NEAR(front.incident, a, 1e-4);
  EXPECT_NEAR(front.reflected, a, 1e-4);
  EXPECT_LT(front.diffracted, 0.2 * a);
  EXPECT_EQ(s.probe(0, 25.0f, 30.0f).reflected, 0.0f);
}

// Fournier-Reeves depth effects on a planar beach: the orbit's horizontal excursion (fold) and the
// crest's lean grow as the water shoals, and never pass the fold-free limit sqrt(Q^2 + L^2) <= 0.9.
TEST(SeaSurface, ShoalingFlattensOrbitsAndLeansCrestsWithoutFolding) {
  houle::Scene scene = beach();
  scene.trains[0].direction_deg = 90.0;
  scene.trains[0].steepness = 1.0;
  houle::SeaSurface s = build(scene);
  const houle::TrainGrid& g = s.grids()[0];
  ASSERT_GE(g.nx, 2u);
  double worst = 0.0;
  // Fold and lean are per metre of amplitude: Q = fold |B|, L = lean |B|.
  const auto b = [](const houle::TrainGrid& grid, std::size_t n) { return std::hypot(double(grid.b_re[n]), double(grid.b_im[n])); };
  for (std::size_t n = 0; n < std::size_t(g.nx) * g.ny; ++n) worst = std::max(worst, std::hypot(double(g.fold[n]), double(g.lean[n])) * b(g, n));
  std::printf("beach: max sqrt(Q^2 + L^2) = %.6f (limit 0.9)\n", worst);
  EXPECT_LE(worst, 0.9 + 1e-6);
  // Five times the amplitude: the tracer's breaking cap H <= 0.142 L tanh(kh), i.e. kA <= 0.142 pi
  // tanh(kh), bounds the fold by q 0.142 pi (q = 1 here) before the fold-free limit is needed.
  houle::Scene steep = scene;
  steep.trains[0].amplitude *= 5.0;
  const houle::SeaSurface s5 = build(steep);
  const houle::TrainGrid& g5 = s5.grids()[0];
  double worst5 = 0.0;
  for (std::size_t n = 0; n < std::size_t(g5.nx) * g5.ny; ++n) worst5 = std::max(worst5, double(g5.fold[n]) * b(g5, n));
  std::printf("steep beach: max fold %.6f (breaking bound %.6f)\n", worst5, 0.142 * std::numbers::pi);
  // 1 % slack: nodes average A and k over the splat's tent (radius 1.5 m, 7.5 cm of depth on this
  // 1:20 slope) but take kh at their own depth, so a node's kA coth(kh) can exceed its samples' by that much.
  EXPECT_LE(worst5, 1.01 * 0.142 * std::numbers::pi);
  EXPECT_GT(worst5, 0.8 * 0.142 * std::numbers::pi);  // the cap is reached, not avoided
  // Along the middle column, deep (y = 10 m) to shallow (y = 90 m): where the limit is not reached,
  // Q / A = q k coth(kh) and L / Q = e^{-kh} exactly, with h the floor's depth at the node.
  const houle::Bathymetry floor(scene.floor);
  const std::size_t i = g.nx / 2;
  double previous_ratio = 0.0;
  for (double y = 10.0; y <= 90.0; y += 10.0) {
    const std::size_t n = std::size_t(std::lround((y - g.origin_y) / g.cell)) * g.nx + i;
    const double x = g.origin_x + double(i) * g.cell, yn = g.origin_y + double(n / g.nx) * g.cell;
    const double k = std::hypot(double(g.kx[n]), double(g.ky[n])), kh = k * floor.depth(x, yn);
    ASSERT_GT(b(g, n), 0.0);
    EXPECT_NEAR(g.fold[n], k / std::tanh(kh), 1e-5) << "y = " << y;
    EXPECT_NEAR(g.lean[n] / g.fold[n], std::exp(-kh), 1e-5) << "y = " << y;
    EXPECT_GT(std::exp(-kh), previous_ratio);  // shoaling all the way
    previous_ratio = std::exp(-kh);
  }
}

// Trains are resampled on several threads: the same bits on one or two (the built-in coast: three
// traced trains, a jetty, reflected waves).
TEST(SeaSurface, TheSameOnOneOrTwoThreads) {
  const houle::Scene scene = houle::builtin_coast();
  const houle::WaveField field = houle::trace_wave_field(scene, 2).value();
  const houle::SeaSurface one = houle::SeaSurface::build(scene, field, 1.0f, houle::SeaParts::drop, 1).value();
  const houle::SeaSurface two = houle::SeaSurface::build(scene, field, 1.0f, houle::SeaParts::drop, 2).value();
  ASSERT_EQ(one.trains().size(), two.trains().size());
  for (std::size_t t = 0; t < one.trains().size(); ++t) {
    const houle::TrainField &a = one.trains()[t], &b = two.trains()[t];
    EXPECT_EQ(a.phi, b.phi) << t;
    EXPECT_EQ(a.b_re, b.b_re) << t;
    EXPECT_EQ(a.b_im, b.b_im) << t;
    EXPECT_EQ(a.kx, b.kx) << t;
    EXPECT_EQ(a.ky, b.ky) << t;
    EXPECT_EQ(a.fold, b.fold) << t;
    EXPECT_EQ(a.lean, b.lean) << t;
  }
  EXPECT_EQ(one.height_bound(), two.height_bound());
  EXPECT_EQ(one.diffraction_work().evaluations, two.diffraction_work().evaluations);
  EXPECT_GT(one.diffraction_work().evaluations, 0u);
}

// Each thread of the build reuses its working arrays from train to train: a train's grid must be
// the same bits whichever trains the thread resampled before it. The built-in coast's trains in
// reverse order on one thread (each then follows other trains, or none), with each wave model.
TEST(SeaSurface, ATrainsGridDoesNotDependOnTheTrainsResampledBeforeIt) {
  for (const houle::WaveModelKind kind : {houle::WaveModelKind::rays, houle::WaveModelKind::parabolic}) {
    houle::Scene scene = houle::builtin_coast();
    scene.wave_model.kind = kind;
    const houle::WaveField field = houle::trace_wave_field(scene, 2).value();
    const std::size_t count = scene.trains.size();
    houle::Scene reversed = scene;
    std::reverse(reversed.trains.begin(), reversed.trains.end());
    houle::WaveField reversed_field = field;
    std::reverse(reversed_field.trains.begin(), reversed_field.trains.end());
    for (houle::ReflectedWave& r : reversed_field.reflections) r.train = count - 1 - r.train;
    ASSERT_FALSE(field.reflections.empty());
    const houle::SeaSurface a = houle::SeaSurface::build(scene, field, 1.0f, houle::SeaParts::keep, 1).value();
    const houle::SeaSurface b = houle::SeaSurface::build(reversed, reversed_field, 1.0f, houle::SeaParts::keep, 1).value();
    ASSERT_EQ(a.trains().size(), count);
    ASSERT_EQ(b.trains().size(), count);
    for (std::size_t t = 0; t < count; ++t) {
      const houle::TrainField &x = a.trains()[t], &y = b.trains()[count - 1 - t];
      ASSERT_FALSE(x.phi.empty());
      EXPECT_EQ(x.model, kind);
      for (const auto field_of : {&houle::TrainField::phi, &houle::TrainField::b_re, &houle::TrainField::b_im,
                                  &houle::TrainField::kx, &houle::TrainField::ky, &houle::TrainField::fold,
                                  &houle::TrainField::lean, &houle::TrainField::breaking, &houle::TrainField::diffraction,
                                  &houle::TrainField::incident, &houle::TrainField::diffracted, &houle::TrainField::reflected}) {
        EXPECT_EQ(x.*field_of, y.*field_of) << t;
      }
    }
  }
}

TEST(SeaSurface, BreakingMarksTheSurfZoneAndTheSurfMapFollows) {
  // beach() up to its shoreline and beyond: a 0.4 m swell on a 1:20 beach. Where the water is too
  // shallow for the shoaled wave (2 A > gamma_b h, gamma_b = 0.78, h below about 1.2 m) the cap holds
  // it: the node breaks (1); offshore, in 5 m of water or more, nothing breaks. The surf map carries
  // the same measure with the waves' direction; a deep sea has none (empty map: no foam work).
  houle::Scene scene = beach();
  scene.domain.y_max = 160.0;
  const houle::SeaSurface sea = build(scene);
  const houle::TrainField& f = sea.trains()[0];
  const houle::TrainGrid& g = sea.grids()[0];
  ASSERT_EQ(f.breaking.size(), std::size_t(g.nx) * g.ny);
  const houle::Bathymetry floor(scene.floor);
  int surf = 0, calm = 0;
  for (std::uint32_t j = 0; j < g.ny; ++j) {
    for (std::uint32_t i = 0; i < g.nx; ++i) {
      const double x = g.origin_x + double(i) * g.cell, y = g.origin_y + double(j) * g.cell, h = floor.depth(x, y);
      const float b = f.breaking[std::size_t(j) * g.nx + i];
      if (x < 10.0 || x > 90.0) continue;  // away from the domain's side edges
      if (h > 0.05 && h < 0.5) {
        EXPECT_EQ(b, 1.0f) << x << ", " << y << ": " << h << " m";
        ++surf;
      }
      if (h > 5.0) {
        EXPECT_EQ(b, 0.0f) << x << ", " << y << ": " << h << " m";
        ++calm;
      }
    }
  }
  EXPECT_GT(surf, 100);
  EXPECT_GT(calm, 1000);
  const houle::SurfMap m = sea.surf_map(scene);
  ASSERT_EQ(m.nx, g.nx);
  const std::size_t n = std::size_t(std::lround((147.0 - m.origin_y) / m.cell)) * m.nx + std::size_t(std::lround((50.0 - m.origin_x) / m.cell));
  EXPECT_EQ(m.foam[n], 1.0f);  // 0.15 m deep
  EXPECT_GT(m.dir_y[n], 0.5f);  // travelling shoreward
  EXPECT_EQ(build(deep_sea()).surf_map(deep_sea()).nx, 0u);
}

TEST(SeaSurface, FoamIsCarriedBehindTheBreakLineAndDecays) {
  // A 0.4 m swell straight at a 1:20 beach with a bar at y = 100 m: the waves break on the bar (0.5 m
  // deep on its crest), cross a trough up to 4 m deep where they break no more, and break again near the
  // shore. Foam must be carried shoreward from the bar and fade with the distance travelled: in the
  // trough, along x = 50, a node s metres behind the last node where the waves broke (breaking = 1)
  // and s0 behind the last where they began to (breaking > 0) has foam between e^{-s / L_min} and
  // e^{-s0 / L_max} (L = foam_decay_wavelengths local wavelengths, their range over the trough), never
  // rising shoreward until the waves break again; nowhere less than the breaking measure itself.
  // Before the foam was carried, the trough had none.
  houle::Scene scene = beach();
  scene.domain.y_max = 160.0;
  scene.trains[0].direction_deg = 90.0;
  scene.floor.bars.push_back({{0.0, 100.0}, 0.0, 8.0, 2.0});
  const houle::SeaSurface sea = build(scene);
  const houle::TrainField& f = sea.trains()[0];
  const houle::TrainGrid& g = sea.grids()[0];
  const houle::SurfMap m = sea.surf_map(scene);
  ASSERT_EQ(m.nx, g.nx);
  for (std::size_t n = 0; n < f.breaking.size(); ++n) EXPECT_GE(m.foam[n], f.breaking[n]);
  const std::size_t i = std::size_t(std::lround((50.0 - g.origin_x) / g.cell));
  const auto node = [&](std::size_t j) { return j * g.nx + i; };
  // Walk shoreward from the bar's crest to the first node where the waves break again.
  std::size_t j = std::size_t(std::lround((100.0 - g.origin_y) / g.cell));
  ASSERT_EQ(f.breaking[node(j)], 1.0f) << "the waves break on the bar";
  std::size_t last_broken = j, last_breaking = j;
  while (j + 1 < g.ny && f.breaking[node(j + 1)] > 0.0f) {
    ++j;
    if (f.breaking[node(j)] == 1.0f) last_broken = j;
    last_breaking = j;
  }
  std::size_t end = j + 1;
  while (end < g.ny && f.breaking[node(end)] == 0.0f) ++end;
  ASSERT_GT(end - last_breaking, 20u) << "a trough of some metres where nothing breaks";
  double l_min = 1e30, l_max = 0.0;
  for (std::size_t t = last_broken; t < end; ++t) {
    const double l = houle::foam_decay_wavelengths * 2.0 * 3.141592653589793 / std::hypot(f.kx[node(t)], f.ky[node(t)]);
    l_min = std::min(l_min, l);
    l_max = std::max(l_max, l);
  }
  float before = m.foam[node(last_breaking)];
  std::size_t carried = 0;
  for (std::size_t t = last_breaking + 1; t < end; ++t) {
    const double s = double(t - last_broken) * g.cell, s0 = double(t - last_breaking) * g.cell;
    const float foam = m.foam[node(t)];
    EXPECT_LE(foam, before) << "y " << g.origin_y + double(t) * g.cell;
    EXPECT_LE(foam, std::exp(-s0 / l_max) * 1.0001) << "y " << g.origin_y + double(t) * g.cell;
    if (std::exp(-s / l_min) > 0.01) {
      EXPECT_GE(foam, std::exp(-s / l_min) * 0.9999) << "y " << g.origin_y + double(t) * g.cell;
    }
    carried += foam > 0.1f;
    before = foam;
  }
  std::printf("foam behind the bar: %zu nodes over 0.1 in a trough of %zu; L %.1f-%.1f m\n", carried,
              end - last_breaking - 1, l_min, l_max);
  EXPECT_GT(carried, 10u);
}

TEST(SeaSurface, TheSeaBeyondTheDomainsSideContinuesItsEdge) {
  // deep_sea()'s train on beach() up to y = 160: where the domain's side (x = 100) crosses the surf zone the sea
  // beyond it must be the sea at the edge, as the floor is (a beach goes on along its shore). Before,
  // the sea beyond was the unshoaled far field: the surf stopped at the side with a step in the height.
  houle::Scene scene = beach();
  scene.domain.y_max = 160.0;
  houle::SeaSurface sea = build(scene);
  sea.set_time(2.0);
  double worst_step = 0.0, worst_slope = 0.0;
  for (float y = 100.0f; y < 148.0f; y += 1.7f) {
    const houle::TrainProbe edge = sea.probe(0, 100.0f, y), beyond = sea.probe(0, 130.0f, y);
    EXPECT_EQ(beyond.amplitude, edge.amplitude) << "y " << y;
    EXPECT_EQ(beyond.wavelength, edge.wavelength) << "y " << y;
    const float xs[2] = {100.0f - 1e-3f, 100.0f + 1e-3f}, ys[2] = {y, y};
    float h[2], gx[2], gy[2];
    sea.eval(xs, ys, 2, h, gx, gy);
    // Continuous: across 2 mm the height changes by its slope there, nothing more.
    worst_step = std::max(worst_step, double(std::fabs(h[1] - h[0] - 1e-3f * (gx[0] + gx[1]))));
    worst_slope = std::max(worst_slope, double(std::fabs(gx[0])));
  }
  std::printf("across the side: largest height step beyond the slope's %.2e m (slope up to %.2f)\n", worst_step, worst_slope);
  EXPECT_LT(worst_step, 1e-5);
  // The surf map reads the same: foam beyond the side where the edge has it.
  const houle::SurfMap m = sea.surf_map(scene);
  ASSERT_GT(m.nx, 0u);
  EXPECT_GT(m.foam[std::size_t(std::lround((145.0 - m.origin_y) / m.cell)) * m.nx + m.nx - 1], 0.5f);
}

TEST(SeaSurface, FoamBehindAShoalFollowsTheWavesDriftAndSpreads) {
  // Two equal swells at 60 and 120 degrees over a round shoal on beach(): they break over its crest,
  // and the foam they leave floats on the water that both move, straight shoreward (their drifts'
  // sum), spreading as it goes. Before, each train's foam went its own way (two streaks at 45 degrees,
  // none straight behind the shoal) and kept its width.
  houle::Scene scene = beach();
  scene.domain = {0.0, 0.0, 200.0, 160.0};
  scene.trains[0].amplitude = 0.3;
  scene.trains.push_back(scene.trains[0]);
  scene.trains[1].direction_deg = 120.0;
  scene.floor.shoals.push_back({{100.0, 60.0}, 8.0, 8.0, 0.0, 3.5});  // 1.0 m deep on its crest
  const houle::SeaSurface sea = build(scene);
  const houle::SurfMap m = sea.surf_map(scene);
  ASSERT_GT(m.nx, 0u);
  const auto foam = [&](double x, double y) {
    return m.foam[std::size_t(std::lround((y - m.origin_y) / m.cell)) * m.nx + std::size_t(std::lround((x - m.origin_x) / m.cell))];
  };
  // Where the breaking over the shoal ends along x = 100, and the foam's width (over 0.2) behind it.
  double end = 60.0;
  for (const houle::TrainField& f : sea.trains()) {
    const houle::TrainGrid& g = sea.grids()[0];
    for (double y = 60.0; y < 90.0; y += g.cell) {
      const std::size_t n = std::size_t(std::lround((y - g.origin_y) / g.cell)) * g.nx + std::size_t(std::lround((100.0 - g.origin_x) / g.cell));
      if (f.breaking[n] > 0.0f) end = std::max(end, y);
    }
  }
  ASSERT_LT(end, 80.0) << "the waves break over the shoal, not behind it";
  const auto width = [&](double y) {
    double w = 0.0;
    for (double x = 60.0; x < 140.0; x += m.cell) w += foam(x, y) > 0.2f ? m.cell : 0.0;
    return w;
  };
  const double near = width(end + 4.0), far = width(end + 24.0);
  std::printf("foam behind the shoal (breaking ends at y %.1f): %.2f straight behind it 24 m on, width %.1f m 4 m on, %.1f m 24 m on\n",
              end, foam(100.0, end + 24.0), near, far);
  EXPECT_GT(foam(100.0, end + 24.0), 0.3f);
  EXPECT_GT(far, near + 4.0);
}

}  // namespace
