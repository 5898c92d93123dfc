// The SIMD layer's own math against double precision, and the ulp comparator the ISA tests rely on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <random>
#include <vector>

#include "houle/simd/exp.hpp"
#include "houle/simd/simd.hpp"
#include "ulp.hpp"

namespace {

TEST(Ulp, CountsRepresentableFloats) {
  EXPECT_EQ(houle::test::ulp_distance(1.0f, 1.0f), 0);
  EXPECT_EQ(houle::test::ulp_distance(1.0f, std::nextafter(1.0f, 2.0f)), 1);
  EXPECT_EQ(houle::test::ulp_distance(-0.0f, 0.0f), 0);
  EXPECT_EQ(houle::test::ulp_distance(-std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::denorm_min()), 2);
  EXPECT_GT(houle::test::ulp_distance(NAN, 1.0f), 1'000'000'000);
  EXPECT_EQ(houle::test::ulps_of_scale(0.25f, 0.25f, 1.0f), 0);
  EXPECT_EQ(houle::test::ulps_of_scale(0.0f, 1e-30f, 1.0f), 1);  // any difference counts
  EXPECT_EQ(houle::test::ulps_of_scale(1.0f, std::nextafter(1.0f, 2.0f), 1.0f), 1);
  EXPECT_EQ(houle::test::ulps_of_scale(0.0f, 3.0f * 1.1920929e-7f, 1.0f), 3);
}

TEST(Simd, RoundNearestIsExactBelow2Pow22) {
  EXPECT_EQ(houle::simd::round_nearest(2.5f), 2.0f);  // ties to even
  EXPECT_EQ(houle::simd::round_nearest(3.5f), 4.0f);
  EXPECT_EQ(houle::simd::round_nearest(-1.49f), -1.0f);
  EXPECT_EQ(houle::simd::round_nearest(4194303.0f), 4194303.0f);
}

// The scalar reference's floor, which ARMv7 NEON shares (the other ISAs have an instruction for it):
// std::floor bit for bit for every float, zeros' signs and integers past 2^23 included.
TEST(Simd, FloorExactIsStdFloorForEveryFloat) {
  std::vector<float> xs = {0.0f, -0.0f, 0.5f, -0.5f, 1.0f, -1.0f, 2.5f, -2.5f, 4194303.5f, -4194303.5f,
                           8388607.5f, -8388607.5f, 8388609.0f, -8388609.0f, 16777217.0f, 3e38f, -3e38f,
                           1e-40f, -1e-40f, INFINITY, -INFINITY};
  std::mt19937 rng(3);
  for (int i = 0; i < 100000; ++i) {
    std::uint32_t bits = std::uint32_t(rng());
    float x;
    std::memcpy(&x, &bits, sizeof x);
    if (!std::isnan(x)) xs.push_back(x);
  }
  for (const float x : xs) {
    const float got = houle::simd::floor_exact(x), want = std::floor(x);
    ASSERT_EQ(std::memcmp(&got, &want, sizeof got), 0) << x;
  }
  EXPECT_TRUE(std::isnan(houle::simd::floor_exact(NAN)));
}

// min_as_std and max_as_std are std::min and std::max, NaN and signed zeros included: the batches
// follow them (one instruction on x86), not the instruction sets' own rules.
TEST(Simd, MinMaxAsStdAreStdMinMax) {
  const float v[] = {0.0f, -0.0f, 1.0f, -1.0f, NAN, INFINITY, -INFINITY};
  for (const float a : v) {
    for (const float b : v) {
      const float lo = houle::simd::min_as_std(a, b), hi = houle::simd::max_as_std(a, b);
      const float want_lo = std::min(a, b), want_hi = std::max(a, b);
      EXPECT_EQ(std::memcmp(&lo, &want_lo, sizeof lo), 0) << a << " " << b;
      EXPECT_EQ(std::memcmp(&hi, &want_hi, sizeof hi), 0) << a << " " << b;
    }
  }
}

TEST(Simd, SinCosWithin1p2e7OfDouble) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> small(-10.0f, 10.0f), large(-1e4f, 1e4f);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const float x = i % 2 ? small(rng) : large(rng);
    float s, c;
    houle::simd::sincos(x, s, c);
    worst = std::max({worst, std::fabs(s - std::sin(double(x))), std::fabs(c - std::cos(double(x)))});
  }
  EXPECT_LE(worst, 1.2e-7);
  float s, c;
  houle::simd::sincos(0.0f, s, c);
  EXPECT_EQ(s, 0.0f);
  EXPECT_EQ(c, 1.0f);
}

TEST(Simd, ExpWithin2e7RelativeOfDouble) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-87.0f, 88.0f), near(-30.0f, 0.0f);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const float x = i % 2 ? u(rng) : near(rng);  // near: the glint's range
    const double want = std::exp(double(x));
    worst = std::max(worst, std::fabs(double(houle::simd::exp(x)) - want) / want);
  }
  EXPECT_LE(worst, 2e-7);
  EXPECT_EQ(houle::simd::exp(0.0f), 1.0f);
  EXPECT_EQ(houle::simd::exp(-1000.0f), houle::simd::exp(-87.0f));  // clamped, not 0 or denormal
}

TEST(Simd, SinCosReducedIsSinCosBitForBitBelowPiOver4) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-0.78f, 0.78f);
  int mismatches = 0;
  for (int i = 0; i < 200000; ++i) {
    const float x = i == 0 ? 0.0f : i == 1 ? -0.0f : i == 2 ? 0.7799999f : i == 3 ? -0.7799999f : u(rng);
    float s, c, rs, rc;
    houle::simd::sincos(x, s, c);
    houle::simd::sincos_reduced(x, rs, rc);
    mismatches += std::memcmp(&s, &rs, sizeof s) != 0 || std::memcmp(&c, &rc, sizeof c) != 0;
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
