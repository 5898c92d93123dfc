// The sand's colour (kernel/render/src/sand.hpp): wet below, dry above, grain faded with the footprint,
// and every ISA against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "sand.hpp"
#include "ulp.hpp"

namespace {

struct FloorHits {
  std::vector<float> on, x, y, z, footprint;
  houle::detail::SandInput input() const { return {on.data(), x.data(), y.data(), z.data(), footprint.data()}; }
  void add(float o, float px, float py, float pz, float f) {
    on.push_back(o), x.push_back(px), y.push_back(py), z.push_back(pz), footprint.push_back(f);
  }
};

struct Colours {
  std::vector<float> r, g, b;
  explicit Colours(std::size_t n) : r(n, -7.0f), g(n, -7.0f), b(n, -7.0f) {}
  houle::detail::SandOutput output() { return {r.data(), g.data(), b.data()}; }
};

constexpr houle::LinearRgb dry{0.6f, 0.5f, 0.35f};

TEST(Sand, WetBelowDryAboveGrainFadedFarOff) {
  FloorHits h;
  h.add(1.0f, 3.0f, 4.0f, -2.0f, 10.0f);   // under water, far: wet (0.55), no grain
  h.add(1.0f, 3.0f, 4.0f, 0.3f, 10.0f);    // at the wet line: wet
  h.add(1.0f, 3.0f, 4.0f, 0.8f, 10.0f);    // half dry: smoothstep(0.5) = 0.5, k = 0.775
  h.add(1.0f, 3.0f, 4.0f, 5.0f, 10.0f);    // dry
  h.add(0.0f, 3.0f, 4.0f, 5.0f, 10.0f);    // no floor hit
  h.add(1.0f, 3.0f, 4.0f, 5.0f, 0.01f);    // dry, near: the grain shows
  Colours c(h.on.size());
  houle::detail::sand_albedo(houle::Isa::scalar, dry, h.input(), h.on.size(), c.output());
  const float k[] = {0.55f, 0.55f, 0.775f, 1.0f, 0.0f};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_NEAR(c.r[i], dry.r * k[i], 1e-6f) << i;
    EXPECT_NEAR(c.g[i], dry.g * k[i], 1e-6f) << i;
    EXPECT_NEAR(c.b[i], dry.b * k[i], 1e-6f) << i;
  }
  // The grain: +-8 % at most, one factor for the three channels.
  EXPECT_NEAR(c.r[5], dry.r, 0.08f * dry.r);
  EXPECT_NEAR(c.r[5] / dry.r, c.b[5] / dry.b, 1e-5f);
  // Near, it varies along the beach; it never brightens a channel past 1.
  FloorHits walk;
  for (int i = 0; i < 300; ++i) walk.add(1.0f, 0.05f * float(i), 1.0f, 5.0f, 0.01f);
  walk.add(1.0f, 0.0f, 0.0f, 5.0f, 0.01f);
  Colours w(walk.on.size());
  const houle::LinearRgb white{1.0f, 1.0f, 1.0f};
  houle::detail::sand_albedo(houle::Isa::scalar, white, walk.input(), walk.on.size(), w.output());
  const auto [lo, hi] = std::minmax_element(w.r.begin(), w.r.end());
  EXPECT_LT(*lo, 0.97f);
  EXPECT_EQ(*hi, 1.0f);
}

TEST(Sand, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, integer hashing), but for ARMv7 NEON, which flushes
  // subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp.
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
      FloorHits h;
      for (std::size_t k = 0; k < n; ++k) {
        // Beaches from -2 to 3 m, far off the origin and beyond the clamp at 1e6 m; footprints of
        // 1 mm to 3 km, so both lattices fade in and out.
        const float scale = k % 17 == 5 ? 3e6f : 2000.0f;
        h.add(k % 6 == 2 ? 0.0f : 1.0f, scale * (u(rng) - 0.5f), scale * (u(rng) - 0.5f), 5.0f * u(rng) - 2.0f,
              1e-3f * std::exp(15.0f * u(rng)));
      }
      Colours ref(n), got(n);
      houle::detail::sand_albedo(houle::Isa::scalar, dry, h.input(), n, ref.output());
      houle::detail::sand_albedo(isa, dry, h.input(), n, got.output());
      for (std::size_t k = 0; k < n; ++k) {
        for (const auto& [a, b] : {std::pair{ref.r[k], got.r[k]}, std::pair{ref.g[k], got.g[k]}, std::pair{ref.b[k], got.b[k]}}) {
          if (!(std::fabs(a - b) <= (isa == houle::Isa::neon ? 1e-6f : 0.0f))) {
            worst = std::max(worst, houle::test::ulp_distance(a, b));
          }
        }
      }
    }
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("sand_albedo %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(tolerance(isa)));
  }
}

}  // namespace
