#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "houle/render/colour.hpp"
#include "houle/runtime/isa.hpp"
#include "test_vectors.hpp"
#include "ulp.hpp"

namespace {

using houle::LinearRgb;
using houle::Spectrum;

double max_abs_diff(LinearRgb a, LinearRgb b) {
  return std::max({std::fabs(double(a.r) - b.r), std::fabs(double(a.g) - b.g), std::fabs(double(a.b) - b.b)});
}

const LinearRgb nominal_colours[7] = {{1, 1, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

LinearRgb random_colour(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  return {u(rng), u(rng), u(rng)};
}

Spectrum constant_spectrum(double v) {
  Spectrum s;
  s.fill(v);
  return s;
}

TEST(Colour, TablesAreTheCieAndPopeFryData) {
  const auto& d = houle::spectral_data();
  EXPECT_EQ(d.y_bar[35], 1.0);  // y_bar(555 nm)
  // The 5 nm table sums to the 1 nm table's integral (106.86) within the sampling difference.
  double sx = 0, sy = 0, sz = 0;
  for (int i = 0; i < houle::spectrum_samples; ++i) sx += d.x_bar[i], sy += d.y_bar[i], sz += d.z_bar[i];
  EXPECT_NEAR(5 * sx, 106.8655, 0.05);
  EXPECT_NEAR(5 * sy, 106.8569, 0.05);
  EXPECT_NEAR(5 * sz, 106.8923, 0.05);
  // docs/rendering.md 4.3: a(450) = 0.00922, a(500) = 0.0204, a(550) = 0.0565, a(600) = 0.2224, a(700) = 0.624 /m.
  EXPECT_EQ(d.water_absorption[14], 0.00922);
  EXPECT_EQ(d.water_absorption[24], 0.0204);
  EXPECT_EQ(d.water_absorption[34], 0.0565);
  EXPECT_EQ(d.water_absorption[44], 0.2224);
  EXPECT_EQ(d.water_absorption[64], 0.624);
  EXPECT_NEAR(d.d65[36], 100.0, 1e-3);  // 560 nm
}

TEST(Colour, SrgbMatrixMapsD65ToWhiteAndInverts) {
  const houle::CieXyz w = houle::spectrum_to_xyz(houle::spectral_data().d65);
  EXPECT_NEAR(w.x / (w.x + w.y + w.z), 0.3127, 1e-4);
  EXPECT_NEAR(w.y / (w.x + w.y + w.z), 0.3290, 1e-4);
  const houle::CieXyz wn = houle::reflectance_to_xyz(constant_spectrum(1.0), houle::Illuminant::d65);
  EXPECT_NEAR(wn.x, 0.9504, 1e-4);
  EXPECT_NEAR(wn.y, 1.0, 1e-12);
  EXPECT_NEAR(wn.z, 1.0888, 1e-4);
  EXPECT_LE(max_abs_diff(houle::xyz_to_linear_srgb(wn), {1, 1, 1}), 3e-4);
  std::mt19937 rng(1);
  for (int k = 0; k < 100; ++k) {
    const LinearRgb c = random_colour(rng);
    EXPECT_LE(max_abs_diff(houle::xyz_to_linear_srgb(houle::linear_srgb_to_xyz(c)), c), 1e-6);
    EXPECT_NEAR(houle::luminance(c), houle::linear_srgb_to_xyz(c).y, 1e-6);
  }
}

TEST(Colour, SrgbTransferCurve) {
  EXPECT_EQ(houle::srgb_encode(0.0f), 0.0f);
  EXPECT_NEAR(houle::srgb_encode(1.0f), 1.0f, 1e-6);
  EXPECT_EQ(houle::srgb_encode(-0.5f), 0.0f);
  EXPECT_NEAR(houle::srgb_encode(2.0f), 1.0f, 1e-6);
  EXPECT_NEAR(houle::srgb_encode(0.0031308f), 0.04045f, 1e-6);  // the two pieces meet
  EXPECT_EQ(houle::srgb_encode_u8(0.5f), 188);
  EXPECT_EQ(houle::srgb_encode_u8(1.0f), 255);
  EXPECT_EQ(houle::srgb_encode_u8(-1.0f), 0);
  for (int i = 0; i <= 1000; ++i) {
    const float x = float(i) / 1000.0f;
    EXPECT_NEAR(houle::srgb_decode(houle::srgb_encode(x)), x, 2e-6 + 1e-6 * x);
  }
}

TEST(Colour, SmitsRoundTripOfPrimariesWithin1_5PercentAndWhiteIsWhite) {
  // Under Smits' design condition (white E, sRGB primaries), 34 nm bins: docs/rendering.md 4.1 measured 1.3 %.
  double worst = 0.0;
  for (const LinearRgb& c : nominal_colours) {
    const LinearRgb back = houle::reflectance_to_linear_srgb(houle::smits_spectrum(c), houle::Illuminant::equal_energy);
    EXPECT_LE(max_abs_diff(back, c), 0.015) << c.r << " " << c.g << " " << c.b;
    worst = std::max(worst, max_abs_diff(back, c));
  }
  std::printf("smits round trip (E): max error %.4f over white, C, M, Y, R, G, B\n", worst);
  // White is (nearly) the flat reflectance 1 and comes back white under either illuminant.
  const Spectrum w = houle::smits_spectrum({1, 1, 1});
  for (double v : w) EXPECT_NEAR(v, 1.0, 1e-3);
  EXPECT_LE(max_abs_diff(houle::reflectance_to_linear_srgb(w, houle::Illuminant::d65), {1, 1, 1}), 1e-3);
  EXPECT_LE(max_abs_diff(houle::reflectance_to_linear_srgb(w, houle::Illuminant::equal_energy), {1, 1, 1}), 1e-3);
  // Under D65 the same basis is further off (why WaterColourLut corrects distance 0); report it.
  double worst_d65 = 0.0;
  for (const LinearRgb& c : nominal_colours) {
    worst_d65 = std::max(worst_d65, max_abs_diff(houle::reflectance_to_linear_srgb(houle::smits_spectrum(c),
                                                                                   houle::Illuminant::d65), c));
  }
  std::printf("smits round trip (D65, uncorrected): max error %.4f\n", worst_d65);
}

TEST(Colour, SmitsWeightsReconstructTheInput) {
  std::mt19937 rng(2);
  for (int k = 0; k < 1000; ++k) {
    const LinearRgb c = random_colour(rng);
    const houle::SmitsWeights w = houle::smits_weights(c);
    EXPECT_GE(w.white, 0.0f);
    EXPECT_GE(w.secondary_weight, 0.0f);
    EXPECT_GE(w.primary_weight, 0.0f);
    const LinearRgb s = nominal_colours[int(w.secondary)], p = nominal_colours[int(w.primary)];
    const LinearRgb sum{w.white + w.secondary_weight * s.r + w.primary_weight * p.r,
                        w.white + w.secondary_weight * s.g + w.primary_weight * p.g,
                        w.white + w.secondary_weight * s.b + w.primary_weight * p.b};
    EXPECT_LE(max_abs_diff(sum, c), 1e-6);
  }
  // Negative channels count as 0.
  const houle::SmitsWeights w = houle::smits_weights({-0.5f, 0.25f, 0.5f});
  EXPECT_EQ(w.white, 0.0f);
  EXPECT_EQ(w.secondary, houle::SmitsBasis::cyan);
  EXPECT_EQ(w.secondary_weight, 0.25f);
}

TEST(Colour, SeaColoursMatchTestVectors) {
  const auto rows = read_test_vectors("sea_colours.csv").rows;
  ASSERT_EQ(rows.size(), 28u);
  double worst_xy = 0, worst_lin = 0, worst_mapped = 0;
  int worst_8bit = 0;
  for (const auto& r : rows) {
    const double l0 = std::stod(r[1]), sigma = std::stod(r[2]);
    bool named = false;
    for (int s = 0; s < 7; ++s) {
      if (houle::sea_name(houle::Sea(s)) == r[0]) {
        named = true;
        EXPECT_EQ(houle::sea_dominant_wavelength_nm(houle::Sea(s)), l0);
      }
    }
    EXPECT_TRUE(named) << r[0];
    const houle::SeaColour c = houle::sea_colour(l0, sigma, 0.10);
    worst_xy = std::max({worst_xy, std::fabs(c.chromaticity_x - std::stod(r[3])),
                         std::fabs(c.chromaticity_y - std::stod(r[4]))});
    worst_lin = std::max(worst_lin, max_abs_diff(c.unmapped, {std::stof(r[5]), std::stof(r[6]), std::stof(r[7])}));
    worst_mapped = std::max(worst_mapped, max_abs_diff(c.linear, {std::stof(r[8]), std::stof(r[9]), std::stof(r[10])}));
    const int e8[3] = {houle::srgb_encode_u8(c.linear.r), houle::srgb_encode_u8(c.linear.g),
                       houle::srgb_encode_u8(c.linear.b)};
    for (int k = 0; k < 3; ++k) worst_8bit = std::max(worst_8bit, std::abs(e8[k] - std::stoi(r[11 + k])));
    EXPECT_NEAR(houle::luminance(c.linear), 0.10, 1e-6);
    // The mapped spectrum has the mapped colour (up to the D65 grey's 3e-4 off white).
    EXPECT_LE(max_abs_diff(houle::xyz_to_linear_srgb(houle::spectrum_to_xyz(c.radiance)), c.linear), 1e-4);
  }
  EXPECT_LE(worst_xy, 1e-4);  // the file prints 4 decimals
  EXPECT_LE(worst_lin, 1e-5);
  EXPECT_LE(worst_mapped, 1e-5);
  EXPECT_LE(worst_8bit, 1);
  std::printf("sea colours: max error xy %.1e, linear %.1e, mapped %.1e, sRGB8 %d\n", worst_xy, worst_lin,
              worst_mapped, worst_8bit);
}

TEST(Colour, GamutMapKeepsLuminanceAndZeroesTheSmallestChannel) {
  const LinearRgb in{-0.15f, 0.10f, 0.77f};
  const LinearRgb out = houle::gamut_map_to_grey(in);
  EXPECT_NEAR(houle::luminance(out), houle::luminance(in), 1e-6);
  EXPECT_EQ(std::min({out.r, out.g, out.b}), 0.0f);
  EXPECT_GE(out.g, 0.0f);
  const LinearRgb ok{0.2f, 0.3f, 0.4f};
  EXPECT_EQ(max_abs_diff(houle::gamut_map_to_grey(ok), ok), 0.0);
  const LinearRgb dark = houle::gamut_map_to_grey({-1.0f, 0.1f, 0.1f});
  EXPECT_EQ(max_abs_diff(dark, {0, 0, 0}), 0.0);
}

houle::WaterColourLut make_lut(houle::WaterColourParams p = {}) {
  auto lut = houle::WaterColourLut::make(p);
  EXPECT_TRUE(lut.ok()) << (lut.ok() ? "" : lut.error().field + ": " + lut.error().message);
  return std::move(lut).value();
}

TEST(WaterColour, WhiteTransmittanceMatchesTestVectors) {
  const auto rows = read_test_vectors("water_transmittance_rgb.csv").rows;
  ASSERT_EQ(rows.size(), 43u);
  const houle::WaterColourLut lut = make_lut();
  double worst_exact = 0, worst_lut = 0;
  for (const auto& r : rows) {
    const double d = std::stod(r[0]);
    const LinearRgb want{std::stof(r[1]), std::stof(r[2]), std::stof(r[3])};
    worst_exact = std::max(worst_exact, max_abs_diff(houle::water_transmittance_rgb(d), want));
    worst_lut = std::max(worst_lut, max_abs_diff(lut.absorbed({1, 1, 1}, float(d)), want));
  }
  EXPECT_LE(worst_exact, 1e-5);  // the file prints 5 decimals
  EXPECT_LE(worst_lut, 1e-3);    // 64 entries, linear interpolation in d
  std::printf("white transmittance 0-100 m: spectral max error %.1e, LUT (64 entries) max error %.1e\n", worst_exact,
              worst_lut);
  // docs/rendering.md 3.4: 1 m -> (0.737, 0.954, 1.000), 5 m -> (0.178, 0.782, 0.989).
  EXPECT_LE(max_abs_diff(houle::water_transmittance_rgb(1.0), {0.737f, 0.954f, 1.000f}), 5e-4);
  EXPECT_LE(max_abs_diff(houle::water_transmittance_rgb(5.0), {0.178f, 0.782f, 0.989f}), 5e-4);
}

TEST(WaterColour, ZeroDistanceIsIdentity) {
  const houle::WaterColourLut lut = make_lut();
  std::mt19937 rng(3);
  for (int k = 0; k < 1000; ++k) {
    LinearRgb c = random_colour(rng);
    if (k < 7) c = nominal_colours[k];
    EXPECT_LE(max_abs_diff(lut.absorbed(c, 0.0f), c), 1e-6) << k;
    EXPECT_LE(max_abs_diff(lut.transmitted(c, 0.0f), c), 1e-6) << k;
    EXPECT_LE(max_abs_diff(lut.transmitted_rgb_approx(c, 0.0f), c), 1e-6) << k;
  }
  EXPECT_EQ(max_abs_diff(lut.sea_part(0.0f), {0, 0, 0}), 0.0);
  // Negative and NaN distances count as 0.
  EXPECT_LE(max_abs_diff(lut.absorbed({0.3f, 0.6f, 0.9f}, -4.0f), {0.3f, 0.6f, 0.9f}), 1e-6);
  EXPECT_LE(max_abs_diff(lut.absorbed({0.3f, 0.6f, 0.9f}, std::numeric_limits<float>::quiet_NaN()),
                         {0.3f, 0.6f, 0.9f}), 1e-6);
}

TEST(WaterColour, InfiniteDistanceIsTheSeaColour) {
  const houle::WaterColourLut lut = make_lut();
  const houle::SeaColour pacific = houle::sea_colour(473.0, 20.0, 0.10);
  EXPECT_EQ(max_abs_diff(lut.sea_colour(), pacific.linear), 0.0);
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_LE(max_abs_diff(lut.transmitted({0.9f, 0.2f, 0.4f}, inf), pacific.linear), 1e-4);
  EXPECT_EQ(max_abs_diff(lut.absorbed({0.9f, 0.2f, 0.4f}, inf), {0, 0, 0}), 0.0);
  EXPECT_LE(max_abs_diff(lut.transmitted_rgb_approx({0.9f, 0.2f, 0.4f}, inf), pacific.linear), 1e-6);
  // sRGB8 of the Pacific at sigma 20 nm: (0, 90, 165) (docs/rendering.md 4.4).
  EXPECT_EQ(houle::srgb_encode_u8(lut.sea_colour().g), 90);
  EXPECT_EQ(houle::srgb_encode_u8(lut.sea_colour().b), 165);
}

// Eq. 12 per wavelength, summed directly (no table): the oracle for the sea term and grey objects.
LinearRgb spectral_eq12(const Spectrum& object_radiance, const Spectrum& sea, const Spectrum& a, double d) {
  Spectrum s{};
  for (int i = 0; i < houle::spectrum_samples; ++i) {
    const double k = std::exp(-a[i] * d);
    s[i] = k * object_radiance[i] + (1.0 - k) * sea[i];
  }
  return houle::xyz_to_linear_srgb(houle::spectrum_to_xyz(s));
}

TEST(WaterColour, LutMatchesSpectralEq12) {
  houle::WaterColourParams p;
  p.sea_dominant_nm = 512.0;  // Senegal coast, in coastal water with some CDOM
  p.sea_sigma_nm = 30.0;
  p.sea_luminance = 0.08;
  p.cdom_absorption_440_per_m = 0.05;
  const houle::WaterColourLut lut = make_lut(p);
  const Spectrum sea = houle::sea_colour(512.0, 30.0, 0.08).radiance;
  const Spectrum a = houle::water_absorption(0.05);
  const houle::CieXyz d65 = houle::spectrum_to_xyz(houle::spectral_data().d65);
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> dist(0.0f, 40.0f), grey(0.0f, 1.0f);
  double worst_sea = 0, worst_grey = 0, worst_colour = 0;
  for (int k = 0; k < 300; ++k) {
    const float d = dist(rng) * dist(rng) / 40.0f;  // more samples near the surface
    worst_sea = std::max(worst_sea, max_abs_diff(lut.sea_part(d), spectral_eq12(Spectrum{}, sea, a, d)));
    // A grey object: the white basis, which needs no correction at distance 0.
    const float g = grey(rng);
    Spectrum obj{};
    for (int i = 0; i < houle::spectrum_samples; ++i) obj[i] = g * houle::spectral_data().d65[i] / d65.y;
    worst_grey = std::max(worst_grey, max_abs_diff(lut.absorbed({g, g, g}, d), spectral_eq12(obj, Spectrum{}, a, d)));
    // Any colour: the spectral answer for Smits' spectrum, up to the distance-0 correction (<= 7 %).
    const LinearRgb c = random_colour(rng);
    const Spectrum refl = houle::smits_spectrum(c);
    for (int i = 0; i < houle::spectrum_samples; ++i) obj[i] = refl[i] * houle::spectral_data().d65[i] / d65.y;
    worst_colour = std::max(worst_colour, max_abs_diff(lut.absorbed(c, d), spectral_eq12(obj, Spectrum{}, a, d)));
  }
  EXPECT_LE(worst_sea, 1e-3 * 0.08 / 0.10);
  EXPECT_LE(worst_grey, 1e-3);
  EXPECT_LE(worst_colour, 0.08);
  std::printf("water LUT vs spectral eq. 12 (CDOM 0.05/m): sea term %.1e, grey objects %.1e, "
              "colours %.3f (Smits D65 correction)\n", worst_sea, worst_grey, worst_colour);
}

TEST(WaterColour, RgbApproximationIsTheCheapOption) {
  houle::WaterColourParams p;
  p.sea_luminance = 0.0;  // isolate the absorption
  const houle::WaterColourLut lut = make_lut(p);
  // Exact at the fit distance for white.
  EXPECT_LE(max_abs_diff(lut.transmitted_rgb_approx({1, 1, 1}, 2.0f), houle::water_transmittance_rgb(2.0)), 1e-5);
  const auto a = lut.rgb_absorption_per_m();
  std::printf("rgb approximation: a = (%.4f, %.4f, %.4f) /m fitted at 2 m\n", a[0], a[1], a[2]);
  // Its error against the LUT, per distance band, over random colours (reported; bounded loosely).
  std::mt19937 rng(5);
  const float bands[] = {1.0f, 3.0f, 10.0f, 30.0f};
  float lo = 0.0f;
  const houle::WaterColourLut full = make_lut();
  for (float hi : bands) {
    std::uniform_real_distribution<float> dist(lo, hi);
    double worst = 0.0, worst_full = 0.0;
    for (int k = 0; k < 2000; ++k) {
      const LinearRgb c = random_colour(rng);
      const float d = dist(rng);
      worst = std::max(worst, max_abs_diff(lut.transmitted_rgb_approx(c, d), lut.transmitted(c, d)));
      worst_full = std::max(worst_full, max_abs_diff(full.transmitted_rgb_approx(c, d), full.transmitted(c, d)));
    }
    std::printf("rgb approximation vs LUT, d in [%g, %g) m: max |error| %.3f (absorption only), %.3f (with I_sea)\n",
                lo, hi, worst, worst_full);
    if (hi <= 3.0f) {
      EXPECT_LE(worst, 0.1);
    }
    lo = hi;
  }
}

TEST(WaterColour, MixIsTheLightsPathAddedToTheView) {
  // mix(o, d, s, e) = gamut_map(absorbed(o, d + s) + sea_part(d) e); transmitted is mix(o, d, 0, 1).
  const houle::WaterColourLut lut = make_lut();
  const LinearRgb o{0.7f, 0.5f, 0.2f};
  for (float d : {0.0f, 0.5f, 3.0f, 40.0f}) {
    for (float path : {0.0f, 2.0f}) {
      const LinearRgb a = lut.absorbed(o, d + path), sea = lut.sea_part(d);
      const LinearRgb want = houle::gamut_map_to_grey({a.r + sea.r * 0.8f, a.g + sea.g * 0.8f, a.b + sea.b * 0.8f});
      EXPECT_EQ(max_abs_diff(lut.mix(o, d, path, 0.8f), want), 0.0) << d << " " << path;
    }
    EXPECT_EQ(max_abs_diff(lut.mix(o, d, 0.0f, 1.0f), lut.transmitted(o, d)), 0.0);
  }
  // The light's own path dims the object (its luminance; a channel can rise as the water takes the red
  // and its negative share of blue in sRGB's matrix with it) and turns it towards blue.
  const LinearRgb near = lut.mix(o, 1.0f, 0.0f, 0.0f), deep = lut.mix(o, 1.0f, 2.0f, 0.0f);
  EXPECT_LT(houle::luminance(deep), houle::luminance(near));
  EXPECT_LT(deep.r / deep.b, near.r / near.b);
}

TEST(WaterColour, BatchMixIsTheScalarMixOnEveryIsaIncludingTails) {
  // Stated tolerance: the same bits (+, -, *, simd::div, exact conversions and gathers), but for ARMv7
  // NEON, which flushes subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp.
  houle::WaterColourParams params;
  params.cdom_absorption_440_per_m = 0.05;
  const houle::WaterColourLut lut = make_lut(params);
  std::mt19937 rng(37);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    std::int64_t worst = 0;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 20 + 3)}) {
      // Colours of every channel order, ties and negative channels; distances from 0 to infinity, NaN
      // and negative ones; illuminations from 0 to 2.
      std::vector<float> in[6];
      for (std::size_t k = 0; k < n; ++k) {
        float c[3] = {u(rng) * 1.2f - 0.1f, u(rng), u(rng)};
        if (k % 5 == 1) c[2] = c[0];
        if (k % 7 == 2) c[1] = c[0] = c[2];
        const float d = k % 11 == 3 ? std::numeric_limits<float>::infinity()
                        : k % 13 == 4 ? std::numeric_limits<float>::quiet_NaN()
                        : k % 17 == 5 ? -1.0f
                                      : 100.0f * u(rng) * u(rng);
        const float values[6] = {c[0], c[1], c[2], d, k % 3 == 0 ? 0.0f : 10.0f * u(rng), 2.0f * u(rng)};
        for (int a = 0; a < 6; ++a) in[a].push_back(values[a]);
      }
      std::vector<float> out[3];
      for (auto& v : out) v.assign(n, -7.0f);
      lut.mix(isa, {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data()}, n,
              {out[0].data(), out[1].data(), out[2].data()});
      for (std::size_t k = 0; k < n; ++k) {
        const LinearRgb want = lut.mix({in[0][k], in[1][k], in[2][k]}, in[3][k], in[4][k], in[5][k]);
        const float w[3] = {want.r, want.g, want.b};
        for (int a = 0; a < 3; ++a) {
          if (!(std::fabs(w[a] - out[a][k]) <= (isa == houle::Isa::neon ? 1e-6f : 0.0f))) {
            worst = std::max(worst, houle::test::ulp_distance(w[a], out[a][k]));
          }
        }
      }
    }
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("water mix %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(tolerance(isa)));
  }
}

TEST(WaterColour, RejectsBadParameters) {
  const auto field = [](houle::WaterColourParams p) {
    auto r = houle::WaterColourLut::make(p);
    return r.ok() ? std::string() : r.error().field;
  };
  houle::WaterColourParams p;
  EXPECT_EQ(field(p), "");
  p.sea_sigma_nm = 0.0;
  EXPECT_EQ(field(p), "sea_sigma_nm");
  p = {};
  p.sea_dominant_nm = 300.0;
  EXPECT_EQ(field(p), "sea_dominant_nm");
  p = {};
  p.lut_entries = 2;
  EXPECT_EQ(field(p), "lut_entries");
  p = {};
  p.cdom_absorption_440_per_m = -1.0;
  EXPECT_EQ(field(p), "cdom_absorption_440_per_m");
  p = {};
  p.lut_half_distance_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field(p), "lut_half_distance_m");
}

}  // namespace
