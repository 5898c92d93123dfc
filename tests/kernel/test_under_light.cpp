// The light under the sea (kernel/render/src/under_light.hpp): the light on what the rays into the
// water meet and the shadow masks' asks, against their definition and every ISA against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "shadow_mask.hpp"
#include "ulp.hpp"
#include "under_light.hpp"

namespace {

using houle::detail::ShadowMask;
using Vec3 = std::array<float, 3>;

Vec3 unit(Vec3 v) {
  const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

/// A jetty of two boxes and a buoy, and the sun above the water and refracted below it.
struct Scene {
  Vec3 sun = unit({-0.5f, 0.3f, 0.6f}), sun_water = unit({-0.3f, 0.18f, 0.9f});
  std::vector<houle::RenderBox> boxes{{{0.0f, 0.0f, 0.5f}, {6.0f, 1.0f, 1.5f}, 0.4f},
                                      {{5.0f, 4.0f, 0.0f}, {1.0f, 3.0f, 1.0f}, 0.0f}};
  std::vector<houle::RenderSphere> spheres{{{-6.0f, 5.0f, 0.2f}, 0.8f}};
  ShadowMask sun_mask = ShadowMask::build(boxes, spheres, sun);
  ShadowMask water_mask = ShadowMask::build(boxes, spheres, sun_water);
  houle::detail::UnderLightParams params(bool shadows) const {
    return {{0.21f, 0.3f, 0.42f}, {0.9f, 0.85f, 0.7f}, {sun_water[0], sun_water[1], sun_water[2]},
            {sun[0], sun[1], sun[2]}, 2.0f, shadows, sun_mask.view(), water_mask.view()};
  }
};

struct Row {
  std::vector<float> side, x, y, z, nx, ny, nz, t, met, dx, dy, dz, hit_t, hit_nx, hit_ny, hit_nz, ar, ag, ab;
  houle::detail::UnderLightInput input() const {
    return {side.data(), x.data(),     y.data(),      z.data(),      nx.data(),     ny.data(), nz.data(),
            t.data(),    met.data(),   dx.data(),     dy.data(),     dz.data(),     hit_t.data(), hit_nx.data(),
            hit_ny.data(), hit_nz.data(), ar.data(),  ag.data(),     ab.data()};
  }
};

/// n pixels around the scene's casters: sea hits from above and from below, refracted rays down,
/// hits on the floor, on boxes seen from either side, and rays that meet nothing.
Row random_row(std::size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Row r;
  for (std::size_t k = 0; k < n; ++k) {
    const float side = k % 9 == 4 ? -1.0f : k % 13 == 6 ? 0.0f : 1.0f;
    const Vec3 normal = unit({0.4f * u(rng) - 0.2f, 0.4f * u(rng) - 0.2f, 1.0f});
    const Vec3 d = unit({2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 1.0f, -0.3f - u(rng)});
    const Vec3 h = unit({2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 0.6f});
    r.side.push_back(side);
    r.x.push_back(30.0f * u(rng) - 15.0f), r.y.push_back(30.0f * u(rng) - 15.0f), r.z.push_back(0.6f * u(rng) - 0.3f);
    r.nx.push_back(normal[0]), r.ny.push_back(normal[1]), r.nz.push_back(normal[2]);
    r.t.push_back(300.0f * u(rng));
    r.met.push_back(k % 7 == 3 ? 0.0f : 1.0f);
    r.dx.push_back(d[0]), r.dy.push_back(d[1]), r.dz.push_back(d[2]);
    r.hit_t.push_back(0.1f + 12.0f * u(rng));
    r.hit_nx.push_back(h[0]), r.hit_ny.push_back(h[1]), r.hit_nz.push_back(h[2]);
    r.ar.push_back(u(rng)), r.ag.push_back(u(rng)), r.ab.push_back(u(rng));
  }
  return r;
}

struct Out {
  std::vector<float> lit, ask, r, g, b, path;
  explicit Out(std::size_t n) : lit(n, -7.0f), ask(n, -7.0f), r(n, -7.0f), g(n, -7.0f), b(n, -7.0f), path(n, -7.0f) {}
  houle::detail::UnderLightOutput output() { return {lit.data(), ask.data(), r.data(), g.data(), b.data(), path.data()}; }
};

TEST(UnderLight, LightAndAsksFollowTheirDefinition) {
  const Scene s;
  std::mt19937 rng(5);
  const std::size_t n = 4000;
  const Row row = random_row(n, rng);
  for (const bool shadows : {true, false}) {
    const auto p = s.params(shadows);
    Out o(n);
    houle::detail::under_light(houle::Isa::scalar, p, row.input(), n, o.output());
    std::size_t asked_sea = 0, asked_met = 0, lit_met = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const bool sea = row.side[k] > 0.0f, met = sea && row.met[k] > 0.0f;
      const Vec3 at{row.x[k], row.y[k], row.z[k]};
      // The sea hit: asked where its line along the sun, from just off the surface, may meet a caster.
      const float off = 1e-3f + 1e-4f * row.t[k];
      const bool may_sea = s.sun_mask.may_meet({at[0] + off * row.nx[k], at[1] + off * row.ny[k], at[2] + off * row.nz[k]});
      const int ask_sea = sea && shadows && p.casters_top > at[2] && may_sea ? 1 : 0;
      // The surface met: its normal turned to the ray, lit by the ambient light by its tilt and by the
      // refracted sun where it faces it, asked where either leg of the sun's path may meet a caster.
      const Vec3 d{row.dx[k], row.dy[k], row.dz[k]};
      Vec3 h{row.hit_nx[k], row.hit_ny[k], row.hit_nz[k]};
      if (h[0] * d[0] + h[1] * d[1] + h[2] * d[2] > 0.0f) h = {-h[0], -h[1], -h[2]};
      const Vec3 q{at[0] + row.hit_t[k] * d[0], at[1] + row.hit_t[k] * d[1], at[2] + row.hit_t[k] * d[2]};
      const float cos_sun = h[0] * s.sun_water[0] + h[1] * s.sun_water[1] + h[2] * s.sun_water[2];
      const float hoff = 1e-3f + 1e-4f * row.hit_t[k], depth = std::max(0.0f, -q[2]), rise = depth / s.sun_water[2];
      const Vec3 up{q[0] + rise * s.sun_water[0], q[1] + rise * s.sun_water[1], q[2] + rise * s.sun_water[2]};
      const bool may_met =
          s.water_mask.may_meet({q[0] + hoff * h[0], q[1] + hoff * h[1], q[2] + hoff * h[2]}) ||
          (p.casters_top > up[2] && s.sun_mask.may_meet({up[0] + hoff * s.sun[0], up[1] + hoff * s.sun[1], up[2] + hoff * s.sun[2]}));
      const int ask_met = met && shadows && cos_sun > 0.0f && may_met ? 2 : 0;
      ASSERT_EQ(o.ask[k], float(ask_sea + ask_met)) << k;
      ASSERT_EQ(o.lit[k], sea ? 1.0f : 0.0f) << k;
      asked_sea += ask_sea != 0;
      asked_met += ask_met != 0;
      if (!met) {
        for (const float v : {o.r[k], o.g[k], o.b[k], o.path[k]}) ASSERT_EQ(v, 0.0f) << k;
        continue;
      }
      lit_met += cos_sun > 0.0f;
      const float tilt = 0.5f * (1.0f + h[2]), sunny = cos_sun > 0.0f ? cos_sun : 0.0f;
      EXPECT_NEAR(o.r[k], row.ar[k] * (p.ambient[0] * tilt + p.sun_rgb[0] * sunny), 1e-6f) << k;
      EXPECT_NEAR(o.g[k], row.ag[k] * (p.ambient[1] * tilt + p.sun_rgb[1] * sunny), 1e-6f) << k;
      EXPECT_NEAR(o.b[k], row.ab[k] * (p.ambient[2] * tilt + p.sun_rgb[2] * sunny), 1e-6f) << k;
      EXPECT_NEAR(o.path[k], depth / s.sun_water[2], 1e-6f) << k;
    }
    // The row reaches into the shadows, and out of them: both answers are exercised.
    if (shadows) {
      EXPECT_GT(asked_sea, n / 50);
      EXPECT_LT(asked_sea, n / 2);
      EXPECT_GT(asked_met, n / 50);
      EXPECT_LT(asked_met, n / 2);
    } else {
      EXPECT_EQ(asked_sea + asked_met, 0u);
    }
    EXPECT_GT(lit_met, n / 4);
  }
}

TEST(UnderLight, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, comparisons, gathers), but for ARMv7 NEON, which
  // flushes subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp; the asks exactly everywhere.
  const Scene s;
  std::mt19937 rng(17);
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (const bool shadows : {true, false}) {
      for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                            std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
        const Row row = random_row(n, rng);
        Out ref(n), got(n);
        houle::detail::under_light(houle::Isa::scalar, s.params(shadows), row.input(), n, ref.output());
        houle::detail::under_light(isa, s.params(shadows), row.input(), n, got.output());
        for (std::size_t k = 0; k < n; ++k) {
          ASSERT_EQ(got.ask[k], ref.ask[k]) << houle::isa_name(isa) << " pixel " << k << " of " << n;
          ASSERT_EQ(got.lit[k], ref.lit[k]) << houle::isa_name(isa) << " pixel " << k << " of " << n;
          for (const auto& [a, b] : {std::pair{ref.r[k], got.r[k]}, std::pair{ref.g[k], got.g[k]},
                                     std::pair{ref.b[k], got.b[k]}, std::pair{ref.path[k], got.path[k]}}) {
            if (!(std::fabs(a - b) <= (isa == houle::Isa::neon ? 1e-6f : 0.0f))) {
              worst = std::max(worst, houle::test::ulp_distance(a, b));
            }
          }
        }
      }
    }
    EXPECT_LE(worst, isa == houle::Isa::neon ? 64 : 0) << "ISA " << houle::isa_name(isa);
    std::printf("under_light %s vs scalar: max %lld ulp\n", houle::isa_name(isa).data(), static_cast<long long>(worst));
  }
}

}  // namespace
