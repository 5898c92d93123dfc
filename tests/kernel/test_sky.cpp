#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <random>
#include <utility>
#include <sstream>
#include <string>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/render/optics.hpp"
#include "houle/render/sky.hpp"
#include "houle/runtime/isa.hpp"
#include "angles.hpp"
#include "test_vectors.hpp"
#include "ulp.hpp"

namespace {

using houle_test::pi;
using houle_test::deg;

std::array<float, 3> direction(double zenith_rad, double azimuth_rad) {
  return {float(std::sin(zenith_rad) * std::cos(azimuth_rad)), float(std::sin(zenith_rad) * std::sin(azimuth_rad)),
          float(std::cos(zenith_rad))};
}

houle::PreethamSky make_sky(double turbidity, double sun_zenith_deg, double sun_azimuth_deg = 0.0) {
  auto sky = houle::PreethamSky::make(turbidity, direction(sun_zenith_deg * deg, sun_azimuth_deg * deg));
  EXPECT_TRUE(sky.ok());
  return std::move(sky).value();
}

TEST(Preetham, MatchesTestVectors) {
  const auto rows = numeric_rows(read_test_vectors("preetham_testvectors.csv"));
  ASSERT_EQ(rows.size(), 250u);
  double worst_y = 0, worst_xy = 0, worst_dir_y = 0;
  for (const auto& r : rows) {
    const double t = r[0], sun = r[1] * deg, view = r[2] * deg, phi = r[3] * deg, gamma = r[4] * deg;
    const houle::PreethamSky sky = make_sky(t, r[1]);
    const houle::SkyXyY v = sky.evaluate(view, gamma);
    worst_y = std::max(worst_y, std::fabs(v.luminance_kcd - r[5]) / r[5]);
    worst_xy = std::max({worst_xy, std::fabs(v.x - r[6]), std::fabs(v.y - r[7])});
    // Through a float view direction: gamma comes from a float dot product, ~3e-4 rad off at the sun.
    const houle::SkyXyY w = sky.evaluate(direction(view, phi));
    worst_dir_y = std::max(worst_dir_y, std::fabs(w.luminance_kcd - r[5]) / r[5]);
    EXPECT_NEAR(w.x, r[6], 2e-4);
    EXPECT_NEAR(w.y, r[7], 2e-4);
    (void)sun;
  }
  EXPECT_LE(worst_y, 1e-3);
  EXPECT_LE(worst_xy, 1e-4);
  EXPECT_LE(worst_dir_y, 2e-3);
  std::printf("preetham vs test vectors: max rel Y error %.1e, max xy error %.1e; via float directions %.1e\n",
              worst_y, worst_xy, worst_dir_y);
}

TEST(Preetham, ZenithValuesOfTheReference) {
  // docs/rendering.md 6.1: T = 3, sun at 30 deg: Y_z = 10.41 kcd/m^2, (0.2534, 0.2598);
  // T = 2.5, sun at 60 deg: 4.32, (0.2415, 0.2473).
  const houle::SkyXyY a = make_sky(3.0, 30.0).zenith();
  EXPECT_NEAR(a.luminance_kcd, 10.41, 0.005);
  EXPECT_NEAR(a.x, 0.2534, 5e-5);
  EXPECT_NEAR(a.y, 0.2598, 5e-5);
  const houle::SkyXyY b = make_sky(2.5, 60.0).zenith();
  EXPECT_NEAR(b.luminance_kcd, 4.32, 0.005);
  EXPECT_NEAR(b.x, 0.2415, 5e-5);
  EXPECT_NEAR(b.y, 0.2473, 5e-5);
  // Looking straight up gives the zenith values.
  const houle::PreethamSky sky = make_sky(3.0, 30.0);
  const houle::SkyXyY up = sky.evaluate({0.0f, 0.0f, 1.0f});
  EXPECT_NEAR(up.luminance_kcd, a.luminance_kcd, 1e-9);
  EXPECT_NEAR(up.x, a.x, 1e-9);
}

TEST(Preetham, RejectsBadInput) {
  EXPECT_FALSE(houle::PreethamSky::make(1.0, {0, 0, 1}).ok());
  EXPECT_FALSE(houle::PreethamSky::make(std::nan(""), {0, 0, 1}).ok());
  EXPECT_FALSE(houle::PreethamSky::make(3.0, {0, 0, 0}).ok());
  // A sun below the horizon is put on it.
  const auto low = houle::PreethamSky::make(3.0, {1, 0, -0.2f});
  ASSERT_TRUE(low.ok());
  EXPECT_NEAR(low->sun_zenith_rad(), pi / 2, 1e-12);
}

TEST(SkyLut, MatchesDirectEvaluation) {
  // Error of the bilinear lookup relative to the direct model's luminance at that direction.
  // Stated tolerance: 4 % at worst (at the sun, where the Perez function has a cusp in gamma);
  // 1 % at the 99th percentile; 0.3 % RMS.
  houle::SkyLut lut;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Case {
    double t, sun_zenith, sun_azimuth;
  };
  for (const Case c : {Case{2.0, 10.0, 0.0}, Case{3.0, 30.0, 45.0}, Case{3.0, 60.0, 200.0}, Case{6.0, 80.0, 300.0},
                       Case{2.5, 89.0, 90.0}}) {
    const houle::PreethamSky sky = make_sky(c.t, c.sun_zenith, c.sun_azimuth);
    lut.bake(sky);
    std::vector<double> err;
    for (int k = 0; k < 5000; ++k) {
      const double z = u(rng), phi = 2 * pi * u(rng);
      const auto d = direction(std::acos(z), phi);
      const houle::LinearRgb want = sky.radiance(d), got = lut.lookup(d);
      const double e =
          std::max({std::fabs(got.r - want.r), std::fabs(got.g - want.g), std::fabs(got.b - want.b)}) / houle::luminance(want);
      err.push_back(e);
    }
    std::sort(err.begin(), err.end());
    double sum2 = 0;
    for (double e : err) sum2 += e * e;
    const double rms = std::sqrt(sum2 / double(err.size())), p99 = err[err.size() * 99 / 100], worst = err.back();
    EXPECT_LE(worst, 0.04) << "T " << c.t << " sun " << c.sun_zenith;
    EXPECT_LE(p99, 0.01) << "T " << c.t << " sun " << c.sun_zenith;
    EXPECT_LE(rms, 0.003) << "T " << c.t << " sun " << c.sun_zenith;
    std::printf("sky LUT %dx%d vs direct, T %.1f sun %.0f deg: rel error max %.4f, p99 %.4f, rms %.4f\n",
                houle::SkyLut::width, houle::SkyLut::height, c.t, c.sun_zenith, worst, p99, rms);
  }
}

TEST(SkyLut, BelowTheHorizonAndAcrossTheSeam) {
  const houle::PreethamSky sky = make_sky(3.0, 70.0, 10.0);
  houle::SkyLut lut;
  lut.bake(sky);
  for (double phi = 0.0; phi < 360.0; phi += 7.0) {
    const houle::LinearRgb below = lut.lookup(direction(120.0 * deg, phi * deg));
    const houle::LinearRgb horizon = lut.lookup(direction(pi / 2, phi * deg));
    EXPECT_NEAR(below.g, horizon.g, 1e-5 * horizon.g);  // same texels; the column may differ by an ulp
    // The direct model clamps the same way.
    EXPECT_NEAR(houle::luminance(sky.radiance(direction(120.0 * deg, phi * deg))), houle::luminance(below),
                0.06 * houle::luminance(below));
  }
  // Straight down: finite, the horizon at some azimuth.
  const houle::LinearRgb down = lut.lookup({0.0f, 0.0f, -1.0f});
  EXPECT_TRUE(std::isfinite(down.r) && down.r >= 0.0f);
  // Continuous across the azimuth seam (atan2's +-pi cut and the table's column 0 / width).
  for (double z : {0.05, 0.3, 0.8}) {
    const double th = std::acos(z);
    const houle::LinearRgb a = lut.lookup(direction(th, -1e-4)), b = lut.lookup(direction(th, 1e-4));
    const houle::LinearRgb c = lut.lookup(direction(th, pi - 1e-4)), d = lut.lookup(direction(th, pi + 1e-4));
    EXPECT_NEAR(a.g, b.g, 1e-3 * houle::luminance(a));
    EXPECT_NEAR(c.g, d.g, 1e-3 * houle::luminance(c));
  }
}

TEST(SkyLut, BatchLookupIsTheScalarLookupOnEveryIsaIncludingTails) {
  // Stated tolerance: the same bits (the lookup uses +, -, *, simd::div, simd::sqrt, exact conversions
  // and gathers), but for ARMv7 NEON, which flushes subnormals and so may differ by a few ulp.
  houle::SkyLut lut;
  lut.bake(make_sky(3.0, 50.0, 30.0));
  std::mt19937 rng(17);
  std::normal_distribution<float> g;
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    std::int64_t worst = 0;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 20 + 3)}) {
      std::vector<float> x(n), y(n), z(n);
      for (std::size_t k = 0; k < n; ++k) {
        std::array<float, 3> v{g(rng), g(rng), g(rng)};
        // Every few: the axes, the seam, the zenith, straight down, zero and NaN (which reads texel 0).
        switch (k % 13) {
          case 2: v = {1.0f, 0.0f, 0.0f}; break;
          case 4: v = {-1.0f, -0.0f, 0.0f}; break;
          case 5: v = {0.0f, 0.0f, 1.0f}; break;
          case 7: v = {0.0f, 0.0f, -1.0f}; break;
          case 8: v = {0.0f, 0.0f, 0.0f}; break;
          case 10: v = {std::nanf(""), 0.5f, std::nanf("")}; break;
          default: break;
        }
        const float len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (len > 0.0f && k % 13 != 10) v = {v[0] / len, v[1] / len, v[2] / len};
        x[k] = v[0], y[k] = v[1], z[k] = v[2];
      }
      std::vector<float> r(n, -7.0f), gr(n, -7.0f), b(n, -7.0f);
      lut.lookup(isa, x.data(), y.data(), z.data(), n, r.data(), gr.data(), b.data());
      for (std::size_t k = 0; k < n; ++k) {
        const houle::LinearRgb want = lut.lookup({x[k], y[k], z[k]});
        ASSERT_TRUE(std::isfinite(r[k]) && std::isfinite(gr[k]) && std::isfinite(b[k])) << k;
        for (const auto& [w, got] : {std::pair{want.r, r[k]}, std::pair{want.g, gr[k]}, std::pair{want.b, b[k]}}) {
          worst = std::max(worst, houle::test::ulp_distance(w, got));
        }
      }
    }
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("sky lookup %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(tolerance(isa)));
  }
}

TEST(SunGlint, SlopeDensityIsNormalised) {
  // Integral over the hemisphere of D(h) cos(theta_h) = 1 (midpoint rule in theta_h).
  for (float s : {1e-3f, 0.01f, 0.03f, 0.1f}) {
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const double th = (i + 0.5) * (pi / 2) / n;
      sum += houle::gaussian_slope_density(float(std::cos(th)), s) * std::cos(th) * std::sin(th);
    }
    sum *= 2 * pi * (pi / 2) / n;
    EXPECT_NEAR(sum, 1.0, 2e-3) << "slope variance " << s;
  }
}

TEST(SunGlint, PeaksAtTheMirrorDirectionAndConservesEnergy) {
  const std::array<float, 3> n{0, 0, 1};
  const auto sun = direction(30.0 * deg, 0.0);
  const auto mirror = direction(30.0 * deg, pi);
  const float s = 0.004f;
  // The brightest view is next to the mirror direction: in azimuth exactly, in zenith angle ~0.5 deg
  // towards grazing (the lobe's 1 / cos(theta_v)).
  const float peak = houle::sun_glint(n, mirror, sun, s);
  for (double dphi : {-2.0, -0.5, 0.5, 2.0}) {
    EXPECT_LT(houle::sun_glint(n, direction(30.0 * deg, pi + dphi * deg), sun, s), peak);
  }
  double best = 0.0, best_theta = 0.0;
  for (double th = 20.0; th <= 40.0; th += 0.01) {
    const double g = houle::sun_glint(n, direction(th * deg, pi), sun, s);
    if (g > best) best = g, best_theta = th;
  }
  EXPECT_NEAR(best_theta, 30.0, 1.0);
  EXPECT_NEAR(houle::gaussian_slope_density(1.0f, s), 1.0 / (2.0 * pi * s), 1e-3);  // D's peak: h = n
  // Reflected radiance integrated against cos(theta_v) is the reflected fraction of the sun's
  // irradiance on the surface, E_sun cos(theta_l) R: close to Fresnel at 30 deg for a narrow lobe
  // (a little less: shadowing).
  double sum = 0.0;
  const int nt = 300, np = 600;
  for (int i = 0; i < nt; ++i) {
    const double th = (i + 0.5) * (pi / 2) / nt;
    for (int j = 0; j < np; ++j) {
      const double ph = (j + 0.5) * 2 * pi / np;
      sum += houle::sun_glint(n, direction(th, ph), sun, s) * std::cos(th) * std::sin(th);
    }
  }
  sum *= (pi / 2) / nt * (2 * pi) / np;
  const double expected = std::cos(30.0 * deg) * houle::fresnel_reflectance(float(std::cos(30.0 * deg)), 1.0f, 1.34f);
  EXPECT_NEAR(sum / expected, 1.0, 0.02);
  std::printf("sun glint (slope variance %.3f): reflected / (E cos R) = %.4f\n", s, sum / expected);
  // Nothing from below the surface.
  EXPECT_EQ(houle::sun_glint(n, direction(100.0 * deg, pi), sun, s), 0.0f);
  EXPECT_EQ(houle::sun_glint(n, mirror, direction(95.0 * deg, 0.0), s), 0.0f);
  // A smooth sea still has a finite glint (the sun disc's own spread).
  EXPECT_TRUE(std::isfinite(houle::sun_glint(n, mirror, sun, 0.0f)));
}

TEST(Twilight, SkyDimsByCivilTwilightsFallThenStaysAtNight) {
  const float degree = float(deg);
  const auto lum = [](houle::LinearRgb c) { return houle::luminance(c); };
  // Daylight: untouched; continuous at the horizon.
  for (float h : {0.0f, 0.1f, 1.0f}) {
    const houle::LinearRgb f = houle::twilight_sky_factor(h);
    EXPECT_EQ(f.r, 1.0f);
    EXPECT_EQ(f.g, 1.0f);
    EXPECT_EQ(f.b, 1.0f);
  }
  EXPECT_NEAR(lum(houle::twilight_sky_factor(-1e-6f)), 1.0f, 1e-3f);
  // A factor 10 per 2.5 degrees: 1/251 at the end of civil twilight.
  EXPECT_NEAR(lum(houle::twilight_sky_factor(-2.5f * degree)), 0.1f, 2e-3f);
  EXPECT_NEAR(lum(houle::twilight_sky_factor(-6.0f * degree)), 1.0f / 251.2f, 2e-5f);
  // Night: the floor, blue, from about 8.8 degrees down to the nadir.
  for (float d : {9.0f, 18.0f, 90.0f}) {
    const houle::LinearRgb f = houle::twilight_sky_factor(-d * degree);
    EXPECT_NEAR(lum(f), 3e-4f, 3e-6f) << d;
    EXPECT_GT(f.b, 2.0f * f.r) << d;
  }
  // The sun's disc sets over its diameter.
  EXPECT_EQ(houle::sun_disc_above_horizon(houle::sun_angular_radius_rad), 1.0f);
  EXPECT_EQ(houle::sun_disc_above_horizon(-houle::sun_angular_radius_rad), 0.0f);
  EXPECT_NEAR(houle::sun_disc_above_horizon(0.0f), 0.5f, 1e-6f);
}

}  // namespace
