// The light of sea hits seen from above and their glint (kernel/render/src/sea_light.hpp): what they
// add up, and every ISA against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "houle/render/sky.hpp"
#include "houle/runtime/isa.hpp"
#include "sea_light.hpp"
#include "ulp.hpp"

namespace sea_light_test {

using houle::detail::SeaLightInput;
using houle::detail::SeaLightParams;

enum Field { side, kr, sky_r, sky_g, sky_b, air_hit, refl_r, refl_g, refl_b, under_r, under_g, under_b, lit, nx, ny, nz,
             dx, dy, dz, rough, foam, fields };

struct Row {
  std::vector<float> f[fields];
  explicit Row(std::size_t n) {
    for (auto& v : f) v.assign(n, 0.0f);
  }
  SeaLightInput input(bool with_foam = true) const {
    return {f[side].data(),  f[kr].data(),      f[sky_r].data(),   f[sky_g].data(),   f[sky_b].data(),
            f[air_hit].data(), f[refl_r].data(), f[refl_g].data(), f[refl_b].data(), f[under_r].data(),
            f[under_g].data(), f[under_b].data(), f[lit].data(),   f[nx].data(),      f[ny].data(),
            f[nz].data(),    f[dx].data(),      f[dy].data(),      f[dz].data(),      f[rough].data(),
            with_foam ? f[foam].data() : nullptr};
  }
};

struct Lit {
  std::vector<float> r, g, b, lobe;
  explicit Lit(std::size_t n) : r(n, -7.0f), g(n, -7.0f), b(n, -7.0f), lobe(n, -7.0f) {}
};

Lit light_of(const SeaLightParams& p, const Row& row, houle::Isa isa = houle::Isa::scalar, bool with_foam = true) {
  const std::size_t n = row.f[side].size();
  Lit out(n);
  houle::detail::sea_light(isa, p, row.input(with_foam), n, {out.r.data(), out.g.data(), out.b.data(), out.lobe.data()});
  return out;
}

// The sun 30 degrees above the horizon towards +x; sky scale, sun and ambient per channel.
const SeaLightParams lighting{{2.0f, 3.0f, 4.0f}, {5.0f, 6.0f, 7.0f}, {0.5f, 0.25f, 0.125f}, {0.8660254f, 0.0f, 0.5f}, 0.001f};

// A pixel looking down at 45 degrees along -x (the sun behind the camera), a flat sea.
void flat_from_above(Row& row, std::size_t i) {
  row.f[side][i] = 1.0f, row.f[kr][i] = 0.25f, row.f[lit][i] = 1.0f;
  row.f[sky_r][i] = 1.0f, row.f[sky_g][i] = 2.0f, row.f[sky_b][i] = 3.0f;
  row.f[refl_r][i] = 10.0f, row.f[refl_g][i] = 20.0f, row.f[refl_b][i] = 30.0f;
  row.f[under_r][i] = 0.5f, row.f[under_g][i] = 1.5f, row.f[under_b][i] = 2.5f;
  row.f[nz][i] = 1.0f;
  row.f[dx][i] = -0.70710678f, row.f[dz][i] = -0.70710678f;
}

TEST(SeaLight, FresnelSplitsTheSkyOrWhatTheReflectionMeetsFromTheWaterBelow) {
  Row row(4);
  for (std::size_t i = 0; i < 4; ++i) flat_from_above(row, i);
  row.f[air_hit][1] = 1.0f;  // the reflected ray meets an object: its light, not the sky's
  row.f[kr][2] = 1.0f;       // total reflection: nothing from below, even if it holds a NaN
  row.f[under_r][2] = std::numeric_limits<float>::quiet_NaN();
  row.f[foam][3] = 0.5f;  // half foam over the same sea as pixel 0
  const Lit l = light_of(lighting, row);
  EXPECT_FLOAT_EQ(l.r[0], 0.25f * 2.0f + 0.75f * 0.5f);
  EXPECT_FLOAT_EQ(l.g[0], 0.25f * 6.0f + 0.75f * 1.5f);
  EXPECT_FLOAT_EQ(l.b[0], 0.25f * 12.0f + 0.75f * 2.5f);
  EXPECT_FLOAT_EQ(l.r[1], 0.25f * 10.0f + 0.75f * 0.5f);
  EXPECT_FLOAT_EQ(l.b[1], 0.25f * 30.0f + 0.75f * 2.5f);
  EXPECT_FLOAT_EQ(l.r[2], 2.0f);
  // Foam: white diffuse (0.85) under the ambient of an upward face and the sun at cos 0.5.
  EXPECT_FLOAT_EQ(l.r[3], 0.5f * l.r[0] + 0.5f * 0.85f * (0.5f + 5.0f * 0.5f));
  EXPECT_FLOAT_EQ(l.b[3], 0.5f * l.b[0] + 0.5f * 0.85f * (0.125f + 7.0f * 0.5f));
  // Without a surf map there is no foam.
  EXPECT_EQ(light_of(lighting, row, houle::Isa::scalar, false).r[3], l.r[0]);
  // The sun is behind the camera: no glint lobe reaches it.
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(l.lobe[i], 0.0f) << i;
}

TEST(SeaLight, TheGlintLobeIsFlaggedWhereTheMirrorDirectionMeetsTheSunAndTheSeaIsLit) {
  // Looking down towards the sun at its mirror angle: the lobe's centre.
  Row row(3);
  for (std::size_t i = 0; i < 3; ++i) {
    flat_from_above(row, i);
    row.f[dx][i] = 0.8660254f, row.f[dz][i] = -0.5f;
  }
  row.f[lit][1] = 0.0f;        // in an object's shadow
  row.f[dx][2] = 0.0f, row.f[dy][2] = 0.8660254f;  // 90 degrees off the sun: far outside the lobe
  const Lit l = light_of(lighting, row);
  EXPECT_EQ(l.lobe[0], 1.0f);
  EXPECT_EQ(l.lobe[1], 0.0f);
  EXPECT_EQ(l.lobe[2], 0.0f);
  const SeaLightInput in = row.input();
  EXPECT_TRUE(houle::detail::glint_lobe_at(lighting, in, 0, 0.0f));
  EXPECT_FALSE(houle::detail::glint_lobe_at(lighting, in, 2, 0.01f));
  // sea_glint adds pi sun_glint (sky.hpp) where the lobe is flagged, and leaves the others.
  Lit g = l;
  const std::vector<float> variance(3, 0.002f);
  g.lobe = {1.0f, 0.0f, 0.0f};
  houle::detail::sea_glint(houle::Isa::scalar, lighting, in, variance.data(), 3, {g.r.data(), g.g.data(), g.b.data(), g.lobe.data()});
  const float glint = 3.14159265f * houle::sun_glint({0.0f, 0.0f, 1.0f}, {-0.8660254f, 0.0f, 0.5f}, {0.8660254f, 0.0f, 0.5f}, 0.002f);
  EXPECT_GT(glint, 1.0f);
  EXPECT_FLOAT_EQ(g.r[0], l.r[0] + 5.0f * glint);
  EXPECT_FLOAT_EQ(g.b[0], l.b[0] + 7.0f * glint);
  EXPECT_EQ(g.r[1], l.r[1]);
  EXPECT_EQ(g.r[2], l.r[2]);
}

TEST(SeaLight, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, simd::sqrt, simd::exp), but for ARMv7 NEON, which
  // divides and takes square roots by estimate plus Newton steps (the glint): 64 ulp.
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    std::size_t lit_here = 0, lobes = 0;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
      Row row(n);
      for (std::size_t k = 0; k < n; ++k) {
        row.f[side][k] = k % 7 == 3 ? -1.0f : k % 11 == 4 ? 0.0f : 1.0f;
        row.f[kr][k] = k % 13 == 5 ? 1.0f : 0.02f + 0.5f * u(rng);
        row.f[air_hit][k] = k % 5 == 2 ? 1.0f : 0.0f;
        row.f[lit][k] = k % 9 == 1 ? 0.0f : 1.0f;
        row.f[foam][k] = k % 3 == 0 ? u(rng) : 0.0f;
        for (int c : {sky_r, sky_g, sky_b, refl_r, refl_g, refl_b, under_r, under_g, under_b}) row.f[c][k] = 0.1f + u(rng);
        // Normals and rays about the sun's mirror direction, some inside the lobe.
        const float tilt = 0.2f * (u(rng) - 0.5f);
        const float nl = std::sqrt(1.0f + 2.0f * tilt * tilt);
        row.f[nx][k] = tilt / nl, row.f[ny][k] = tilt / nl, row.f[nz][k] = 1.0f / nl;
        const float a = 0.2f + 1.0f * u(rng), b = 1.0f * (u(rng) - 0.5f);
        row.f[dx][k] = std::cos(a) * std::cos(b), row.f[dy][k] = std::cos(a) * std::sin(b), row.f[dz][k] = -std::sin(a);
        row.f[rough][k] = 0.005f * u(rng);
      }
      Lit ref = light_of(lighting, row), got = light_of(lighting, row, isa);
      // Then the glint where the lobe is flagged, at a variance of the pixel's own.
      std::vector<float> variance(n);
      for (std::size_t k = 0; k < n; ++k) variance[k] = row.f[rough][k] + 0.001f * u(rng);
      houle::detail::sea_glint(houle::Isa::scalar, lighting, row.input(), variance.data(), n,
                               {ref.r.data(), ref.g.data(), ref.b.data(), ref.lobe.data()});
      houle::detail::sea_glint(isa, lighting, row.input(), variance.data(), n, {got.r.data(), got.g.data(), got.b.data(), got.lobe.data()});
      for (std::size_t k = 0; k < n; ++k) {
        EXPECT_EQ(got.lobe[k], ref.lobe[k]) << k;
        if (!(row.f[side][k] > 0.0f)) continue;
        ++lit_here;
        lobes += ref.lobe[k] > 0.0f;
        worst = std::max({worst, houle::test::ulp_distance(ref.r[k], got.r[k]), houle::test::ulp_distance(ref.g[k], got.g[k]),
                          houle::test::ulp_distance(ref.b[k], got.b[k])});
      }
    }
    EXPECT_GT(lit_here, 900u);
    EXPECT_GT(lobes, 50u);  // the lobe test is exercised both ways
    EXPECT_LT(lobes + 50, lit_here);
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("sea_light and sea_glint %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(tolerance(isa)));
  }
}

}  // namespace sea_light_test
