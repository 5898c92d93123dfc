#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "houle/render/framebuffer.hpp"

namespace {

std::uint8_t srgb8_exact(float v) {
  const double c = std::clamp(double(v), 0.0, 1.0);
  const double e = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
  return std::uint8_t(std::lround(e * 255.0));
}

TEST(Framebuffer, Srgb8MatchesTheExactCurveOnEveryFloatInUnitInterval) {
  // Every float in [0, 1], stepping by 64 ulps (16 million values), plus the ends.
  std::uint32_t bits_one;
  const float one = 1.0f;
  std::memcpy(&bits_one, &one, 4);
  int mismatches = 0;
  for (std::uint32_t b = 0; b <= bits_one; b += 64) {
    float v;
    std::memcpy(&v, &b, 4);
    mismatches += houle::srgb8_from_linear(v) != srgb8_exact(v);
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(houle::srgb8_from_linear(-1.0f), 0);
  EXPECT_EQ(houle::srgb8_from_linear(NAN), 0);
  EXPECT_EQ(houle::srgb8_from_linear(2.0f), 255);
}

TEST(Framebuffer, ToneMapRollsHighlightsOffAndDesaturatesThemTowardsWhite) {
  const houle::ToneMap tm{};
  const auto y = [](houle::LinearRgb c) { return houle::luminance(c); };
  // Black for what is not a finite non-negative radiance.
  for (float bad : {-3.0f, NAN, INFINITY}) {
    const houle::LinearRgb d = houle::tone_map({bad, bad, bad}, tm);
    EXPECT_EQ(d.r + d.g + d.b, 0.0f) << bad;
  }
  // The curve: increasing, below 1, and still rising far above 1: highlights roll off, they do not
  // clip (the old per-channel shoulder was flat white from about 1.8 on).
  float last = 0.0f;
  for (float x = 1e-4f; x < 1e4f; x *= 1.1f) {
    const float f = houle::filmic_curve(x);
    EXPECT_GT(f, last) << x;
    EXPECT_LE(f, 1.0f) << x;
    last = f;
  }
  EXPECT_LT(houle::filmic_curve(4.0f), 0.97f);
  EXPECT_GT(houle::filmic_curve(8.0f) - houle::filmic_curve(4.0f), 0.01f);
  EXPECT_NEAR(houle::filmic_curve(0.18f), 0.259f, 0.002f);  // mid grey
  // Grey stays grey; a moderate colour keeps its hue (channel ratios) and gets the curve's luminance.
  const houle::LinearRgb grey = houle::tone_map({0.5f, 0.5f, 0.5f}, tm);
  EXPECT_FLOAT_EQ(grey.r, grey.b);
  EXPECT_NEAR(y(grey), houle::filmic_curve(0.5f), 1e-6f);
  const houle::LinearRgb sea = houle::tone_map({0.05f, 0.2f, 0.3f}, tm);
  EXPECT_NEAR(sea.g / sea.r, 4.0f, 1e-4f);
  EXPECT_NEAR(sea.b / sea.r, 6.0f, 1e-4f);
  EXPECT_NEAR(y(sea), houle::filmic_curve(y({0.05f, 0.2f, 0.3f})), 1e-6f);
  // A saturated highlight goes towards white at the curve's luminance: no channel above 1, and the
  // brighter it is, the less saturated.
  float last_spread = 2.0f;
  for (float e : {2.0f, 8.0f, 32.0f, 128.0f}) {
    const houle::LinearRgb d = houle::tone_map({e, 0.3f * e, 0.05f * e}, tm);
    EXPECT_LE(std::max(d.r, std::max(d.g, d.b)), 1.0f) << e;
    EXPECT_NEAR(y(d), houle::filmic_curve(y({e, 0.3f * e, 0.05f * e})), 1e-5f) << e;
    const float spread = d.r - d.b;
    EXPECT_LT(spread, last_spread) << e;
    last_spread = spread;
  }
  // Exposure multiplies first.
  const houle::LinearRgb a = houle::tone_map({0.1f, 0.2f, 0.3f}, houle::ToneMap{4.0f}), b = houle::tone_map({0.4f, 0.8f, 1.2f}, tm);
  EXPECT_FLOAT_EQ(a.r, b.r);
  EXPECT_FLOAT_EQ(a.b, b.b);
}

TEST(Framebuffer, EncodesEveryFormatTightlyPacked) {
  houle::Framebuffer fb(3, 2);
  for (std::size_t i = 0; i < fb.rgb.size(); i += 3) fb.rgb[i] = 1.0f, fb.rgb[i + 1] = 0.2158605f, fb.rgb[i + 2] = 0.0f;
  for (auto f : {houle::PixelFormat::rgb24, houle::PixelFormat::rgba8, houle::PixelFormat::bgra8, houle::PixelFormat::rgbf32}) {
    std::vector<std::byte> out(houle::bytes_per_pixel(f) * 6 + 1, std::byte{0x5a});
    houle::encode_frame(fb, houle::ToneMap{1.0f}, f, std::span(out).first(out.size() - 1));
    EXPECT_EQ(out.back(), std::byte{0x5a}) << "wrote past the frame";
    const auto* u = reinterpret_cast<const std::uint8_t*>(out.data());
    if (f == houle::PixelFormat::rgb24) {
      EXPECT_EQ(u[3 * 5 + 1], houle::srgb8_from_linear(houle::tone_map({1.0f, 0.2158605f, 0.0f}, houle::ToneMap{1.0f}).g));
    } else if (f == houle::PixelFormat::rgba8) {
      EXPECT_EQ(u[4 * 5 + 3], 255);
    } else if (f == houle::PixelFormat::bgra8) {
      EXPECT_EQ(u[2], houle::srgb8_from_linear(houle::tone_map({1.0f, 0.2158605f, 0.0f}, houle::ToneMap{1.0f}).r));  // red, in third place
    }
    EXPECT_EQ(houle::parse_pixel_format(houle::pixel_format_name(f)), f);
  }
  EXPECT_FALSE(houle::parse_pixel_format("yuv420p").has_value());
  EXPECT_EQ(houle::parse_pixel_format("rgba8"), houle::PixelFormat::rgba8);
  EXPECT_EQ(houle::parse_pixel_format("bgra8"), houle::PixelFormat::bgra8);
}

}  // namespace
