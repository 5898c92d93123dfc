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

TEST(Framebuffer, ToneMapIsIdentityBelowTheKneeAndC1AtIt) {
  const houle::ToneMap tm{};
  EXPECT_EQ(houle::tone_map(0.5f, tm), 0.5f);
  EXPECT_EQ(houle::tone_map(-3.0f, tm), 0.0f);
  EXPECT_EQ(houle::tone_map(NAN, tm), 0.0f);
  EXPECT_LT(houle::tone_map(1e6f, tm), 1.0f + 1e-6f);
  // Right-hand difference quotient at the knee against its analytic value (which tends to 1: C1).
  const double e = 1.0 / 1024.0;
  const double slope = (double(houle::tone_map(0.8f + float(e), tm)) - double(houle::tone_map(0.8f, tm))) / e;
  EXPECT_NEAR(slope, 0.2 * (1.0 - std::exp(-e / 0.2)) / e, 1e-4);
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
      EXPECT_EQ(u[3 * 5 + 1], 128);  // decode(128 / 255) = 0.2158605
    } else if (f == houle::PixelFormat::rgba8) {
      EXPECT_EQ(u[4 * 5 + 3], 255);
    } else if (f == houle::PixelFormat::bgra8) {
      EXPECT_EQ(u[2], houle::srgb8_from_linear(houle::tone_map(1.0f, houle::ToneMap{1.0f})));  // red, in third place
    }
    EXPECT_EQ(houle::parse_pixel_format(houle::pixel_format_name(f)), f);
  }
  EXPECT_FALSE(houle::parse_pixel_format("yuv420p").has_value());
  EXPECT_EQ(houle::parse_pixel_format("rgba8"), houle::PixelFormat::rgba8);
  EXPECT_EQ(houle::parse_pixel_format("bgra8"), houle::PixelFormat::bgra8);
}

}  // namespace
