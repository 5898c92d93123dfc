// Hard cases (docs/physics.md 8, rendering guards of issue 7) swept end to end through the scene build,
// the sea surface and the renderer: each asserts finite, bounded and continuous results and prints
// its worst measured values ("worst:" lines in the test log).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <numbers>
#include <vector>

#include "surface_checks.hpp"

namespace {

using houle::test::FrameStats;
using houle::test::SurfaceSweep;

constexpr double two_pi = 2.0 * std::numbers::pi;
// Linear radiance of any pixel: the sun's glint is the brightest thing (about 2e2 in these scenes'
// units, test_renderer's SunGlintInFrontIsTheBrightestThing); an order of magnitude above that means
// something blew up.
constexpr float max_radiance = 1e4f;

// Frames of one scene at several times (one scene build: under qemu a build of the coast takes seconds).
std::vector<FrameStats> render(const houle::Scene& scene, std::initializer_list<double> times,
                               houle::QualityPreset q = houle::QualityPreset::draft, int w = 64, int h = 36) {
  houle::Expected<houle::Animation> a = houle::Animation::create(scene, houle::quality_preset(q), std::uint32_t(w), std::uint32_t(h), 2);
  EXPECT_TRUE(a) << (a ? std::string() : a.error().field + ": " + a.error().message);
  std::vector<FrameStats> frames(times.size(), FrameStats{false});
  if (!a) return frames;
  houle::Framebuffer fb(w, h);
  std::size_t i = 0;
  for (double t : times) {
    a->render(t, fb);
    frames[i++] = houle::test::frame_stats(fb);
  }
  return frames;
}

FrameStats render(const houle::Scene& scene, double t, houle::QualityPreset q = houle::QualityPreset::draft, int w = 64,
                  int h = 36) {
  return render(scene, {t}, q, w, h).front();
}

void expect_sane_frame(const FrameStats& f, const char* what) {
  std::printf("worst: %s: pixels in [%.4g, %.4g], mean %.4g\n", what, f.min, f.max, f.mean);
  EXPECT_TRUE(f.finite) << what;
  EXPECT_GE(f.min, 0.0f) << what;
  EXPECT_LE(f.max, max_radiance) << what;
  EXPECT_GT(f.mean, 0.0f) << what;  // not a black frame from a silent failure
}

houle::SeaSurface build_sea(const houle::Scene& scene, float cell) {
  houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 2);
  EXPECT_TRUE(field);
  houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), cell);
  EXPECT_TRUE(sea);
  return std::move(sea.value());
}

// Finite, within the surface's own bound, and continuous: a probe step 4 times shorter cuts the
// largest jump to well under half (a seam or fold would keep it). Steps are below the sea grid's
// cell, where the interpolated surface is Lipschitz.
void expect_sane_surface(const SurfaceSweep& s, const char* what, bool continuous = true) {
  std::printf("worst: %s: |h|/bound %.4f, slope %.4f, jump %.3g m at step d, %.3g m at d/4 (ratio %.3f, at %.4g, %.4g m)\n",
              what, s.worst_height_ratio, s.max_slope, s.jump_coarse, s.jump_fine,
              s.jump_fine / std::max(s.jump_coarse, 1e-30f), s.worst_x, s.worst_y);
  EXPECT_TRUE(s.finite) << what;
  EXPECT_LE(s.worst_height_ratio, 1.0f + 1e-5f) << what;
  if (continuous) {
    EXPECT_LE(s.jump_fine, 0.5f * s.jump_coarse + 1e-6f) << what;
  }
}

TEST(HardCases, CameraAtTheSurface) {
  for (double z : {0.0, 1e-4, 0.02, -0.02}) {
    houle::Scene scene = houle::builtin_coast();
    scene.camera.position = {100.0, 100.0, z};  // over 2.3 m of water, looking out to sea
    scene.camera.look_at = {100.0, 0.0, z - 0.5};
    char what[64];
    std::snprintf(what, sizeof what, "camera at z = %g m", z);
    for (const FrameStats& f : render(scene, {0.0, 4.3})) expect_sane_frame(f, what);
  }
}

TEST(HardCases, RaysParallelToTheSea) {
  // A narrow horizontal view: every ray within 0.25 degrees of the horizon, grazing the crests.
  for (double z : {0.3, 2.0, 30.0}) {
    houle::Scene scene = houle::builtin_coast();
    scene.camera.position.z = z;
    scene.camera.look_at = {scene.camera.position.x, scene.camera.position.y + 1000.0, z};
    scene.camera.vertical_fov_deg = 0.5;
    char what[64];
    std::snprintf(what, sizeof what, "horizontal 0.5 deg view from z = %g m", z);
    expect_sane_frame(render(scene, 2.0), what);
  }
}

TEST(HardCases, HugeTimesKeepThePhase) {
  // One train, period 8 s: the surface at t0 + N T equals the surface at t0 to 1e-3 A (docs/physics.md 8.22)
  // whatever N, because omega t is reduced in double before it reaches float.
  houle::Scene scene = houle::builtin_coast();
  scene.trains.resize(1);
  scene.trains[0].period = 8.0;
  scene.trains[0].wavelength.reset();
  const double a = scene.trains[0].amplitude;
  houle::SeaSurface sea = build_sea(scene, 0.5f);
  const double t0 = 0.3;
  constexpr std::size_t n = 400;
  std::array<float, n> xs, ys, h0, h, gx, gy;
  for (std::size_t i = 0; i < n; ++i) {
    xs[i] = float(5.0 + 190.0 * double((i * 37) % n) / double(n));
    ys[i] = float(5.0 + 190.0 * double(i) / double(n));
  }
  sea.set_time(t0);
  sea.eval(xs.data(), ys.data(), n, h0.data(), gx.data(), gy.data());
  for (double periods : {1.25e5, 1.25e7, 1.25e9, 1.25e11}) {  // t = 1e6 s ... 1e12 s
    const double t = t0 + periods * 8.0;
    sea.set_time(t);
    sea.eval(xs.data(), ys.data(), n, h.data(), gx.data(), gy.data());
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      ASSERT_TRUE(std::isfinite(h[i]) && std::isfinite(gx[i]) && std::isfinite(gy[i]));
      worst = std::max(worst, double(std::fabs(h[i] - h0[i])));
    }
    std::printf("worst: t = %.3g s: |h(t) - h(t mod T)| = %.3g A\n", t, worst / a);
    // Beyond 1e11 s a double t itself has an ulp of 1.5e-5 s: the phase error is omega * ulp(t).
    const double tolerance = 1e-3 * a + (two_pi / 8.0) * std::ldexp(1.0, std::ilogb(t) - 52) * a;
    EXPECT_LE(worst, tolerance) << "t = " << t;
  }
  // The full coast (three traced trains, capillary ripples) renders sanely at huge times.
  const std::initializer_list<double> huge = {1e6, 1e8, 1e10};
  const std::vector<FrameStats> frames = render(houle::builtin_coast(), huge);
  for (std::size_t i = 0; i < huge.size(); ++i) {
    const double t = huge.begin()[i];
    char what[64];
    std::snprintf(what, sizeof what, "built-in coast at t = %g s", t);
    expect_sane_frame(frames[i], what);
    sea.set_time(t);
    expect_sane_surface(houle::test::sweep_surface(sea, 0, 0, 200, 200, 0.2f), what);
  }
}

TEST(HardCases, TimeContinuityAtHugeTimes) {
  // The surface moves continuously in time at any t: ten times shorter a step, about ten times
  // smaller the largest change (a phase rounded in float would make it jump by a fixed amount).
  houle::SeaSurface sea = build_sea(houle::builtin_coast(), 0.5f);
  for (double t : {0.0, 1e6, 1e9}) {
    float jump[2] = {0.0f, 0.0f};
    const double steps[2] = {1e-2, 1e-3};
    for (int s = 0; s < 2; ++s) {
      for (int i = 0; i < 200; ++i) {
        const float x = float(10.0 + 0.9 * i), y = float(20.0 + 0.7 * i);
        float h[2], gx, gy;
        sea.set_time(t);
        sea.eval(&x, &y, 1, &h[0], &gx, &gy);
        sea.set_time(t + steps[s]);
        sea.eval(&x, &y, 1, &h[1], &gx, &gy);
        ASSERT_TRUE(std::isfinite(h[0]) && std::isfinite(h[1]));
        jump[s] = std::max(jump[s], std::fabs(h[1] - h[0]));
      }
    }
    std::printf("worst: t = %g s: |dh| %.3g m over 10 ms, %.3g m over 1 ms\n", t, jump[0], jump[1]);
    EXPECT_GT(jump[0], 0.0f);
    EXPECT_LE(jump[1], 0.2f * jump[0] + 1e-6f) << "t = " << t;
  }
}

houle::Scene beach_with_jetty(double size_m) {
  // The built-in coast's layout scaled to a square of size_m: beach, jetty, one train.
  houle::Scene s;
  s.domain = {0.0, 0.0, size_m, size_m};
  s.floor.base.kind = houle::FloorKind::planar_beach;
  s.floor.base.depth = 0.05 * size_m;
  s.floor.base.slope = 0.1;
  s.floor.base.shoreline = {0.0, size_m};
  s.walls.push_back({{{0.3 * size_m, size_m}, {0.3 * size_m, 0.55 * size_m}}, 0.01 * size_m, 0.5, 0.01 * size_m});
  houle::WaveTrain t;
  t.direction_deg = 75.0;
  t.wavelength = 0.08 * size_m;
  t.amplitude = 0.02 * 0.08 * size_m;
  s.trains.push_back(t);
  s.capillary.amplitude = 0.0;
  s.camera.position = {0.5 * size_m, -0.1 * size_m, 0.03 * size_m};
  s.camera.look_at = {0.5 * size_m, 0.5 * size_m, 0.0};
  s.dwt.step = 0.004 * size_m;
  s.dwt.insertion_distance = 0.01 * size_m;
  s.dwt.min_depth = 1e-4 * size_m;
  return s;
}

TEST(HardCases, HugeAndTinyScenes) {
  // 20 m is the smallest: its waves, 0.08 of its size, are the shortest a train may have (L0 >= 1.5 m).
  for (double size : {1000.0, 20.0}) {
    const houle::Scene scene = beach_with_jetty(size);
    ASSERT_TRUE(houle::validate(scene)) << size;
    houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 2);
    ASSERT_TRUE(field);
    const houle::test::AmplitudeWorst aw = houle::test::amplitude_worst(scene, field.value());
    std::printf("worst: %g m scene: %zu samples, 2A/(gamma_b h) %.4f, A/(A0 Ks Kr_max) %.4f\n", size, aw.samples,
                aw.breaking, aw.energy);
    EXPECT_TRUE(aw.finite);
    EXPECT_GT(aw.samples, 100u);
    EXPECT_LE(aw.breaking, 1.0 + 1e-9);
    EXPECT_LE(aw.energy, 1.0 + 1e-9);
    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), float(0.002 * size));
    ASSERT_TRUE(sea);
    char what[64];
    std::snprintf(what, sizeof what, "%g m scene", size);
    for (double t : {0.0, 3.7, 1e6}) {
      sea->set_time(t);
      // Probe steps below the grid's cell (0.002 size): the interpolant must be continuous there.
      expect_sane_surface(houle::test::sweep_surface(sea.value(), 0, 0, size, size, float(0.001 * size)), what);
    }
    // Draft's sea grid is 1 m: the 1.6 m waves span under two cells, their phase interpolated across them.
    expect_sane_frame(render(scene, 2.0), what);
  }
}

TEST(HardCases, BreakingLimitSteepness) {
  // The steepest train validation accepts (A0 = 0.071 L0, the Stokes limit) with the fullest
  // Gerstner profile (q = 1), in deep water (analytic) and shoaling up a beach (traced).
  for (bool beach : {false, true}) {
    houle::Scene scene = houle::builtin_coast();
    scene.walls.clear();
    scene.trains.resize(1);
    scene.trains[0].period.reset();
    scene.trains[0].wavelength = 12.0;
    scene.trains[0].amplitude = 0.071 * 12.0;
    scene.trains[0].steepness = 1.0;
    if (!beach) scene.floor = {};
    ASSERT_TRUE(houle::validate(scene));
    houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 2);
    ASSERT_TRUE(field);
    EXPECT_EQ(field->trains[0].analytic, !beach);
    const houle::test::AmplitudeWorst aw = houle::test::amplitude_worst(scene, field.value());
    const char* what = beach ? "Stokes-limit train on a beach" : "Stokes-limit train in deep water";
    std::printf("worst: %s: 2A/(gamma_b h) %.4f, A/(A0 Ks Kr_max) %.4f\n", what, aw.breaking, aw.energy);
    EXPECT_TRUE(aw.finite);
    EXPECT_LE(aw.breaking, 1.0 + 1e-9);
    EXPECT_LE(aw.energy, 1.0 + 1e-9);
    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), 0.5f);
    ASSERT_TRUE(sea);
    for (double t : {0.0, 1.1, 2.9}) {
      sea->set_time(t);
      expect_sane_surface(houle::test::sweep_surface(sea.value(), 0, 0, 200, 200, 0.1f), what);
    }
    expect_sane_frame(render(scene, 1.1), what);
  }
}

TEST(HardCases, VeryLongAndVeryShortWavesForTheDepth) {
  struct Case {
    const char* what;
    double period, depth, amplitude;
  };
  // kh = 0.07 (40 s swell over 3 m: shallow, breaking-limited) and kh = 120 (1 s chop over 30 m, the
  // shortest period a train may have: a wavelength of 1.56 m, three of the sea grid's 0.5 m cells and
  // four of the rays' 0.4 m steps).
  for (const Case& c : {Case{"40 s swell over 3 m", 40.0, 3.0, 1.5}, Case{"1 s chop over 30 m", 1.0, 30.0, 0.01}}) {
    houle::Scene scene = houle::builtin_coast();
    scene.trains.resize(1);
    scene.trains[0].period = c.period;
    scene.trains[0].wavelength.reset();
    scene.trains[0].amplitude = c.amplitude;
    scene.floor.base.depth = c.depth;
    // Rays stop at 0.01 L0 by default: 25 m for the swell, deeper than the whole sea. Down to min_depth.
    scene.dwt.min_depth_wavelengths = 0.0;
    ASSERT_TRUE(houle::validate(scene)) << c.what;
    houle::Expected<houle::WaveField> field = houle::trace_wave_field(scene, 2);
    ASSERT_TRUE(field);
    const houle::test::AmplitudeWorst aw = houle::test::amplitude_worst(scene, field.value());
    std::printf("worst: %s: %zu samples, 2A/(gamma_b h) %.4f, A/(A0 Ks Kr_max) %.4f\n", c.what, aw.samples,
                aw.breaking, aw.energy);
    EXPECT_TRUE(aw.finite);
    EXPECT_GT(aw.samples, 1000u) << c.what;
    EXPECT_LE(aw.breaking, 1.0 + 1e-9);
    EXPECT_LE(aw.energy, 1.0 + 1e-9);
    houle::Expected<houle::SeaSurface> sea = houle::SeaSurface::build(scene, field.value(), 0.5f);
    ASSERT_TRUE(sea);
    const double k_max = houle::linear_wave(two_pi / c.period, 0.02).k;  // the shortest wavelength, at h_min
    sea->set_time(5.0);
    const float step = std::min(0.2f, float(0.1 * two_pi / k_max));  // below the cell and the wavelength
    // The jetty's reflected wave is part of its train's field (one carrier per node): continuous with it.
    expect_sane_surface(houle::test::sweep_surface(sea.value(), 0, 0, 200, 200, step), c.what);
    expect_sane_frame(render(scene, 5.0), c.what);
  }
}

}  // namespace
