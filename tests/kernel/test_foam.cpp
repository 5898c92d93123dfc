// The surf foam kernel (kernel/render/src/foam.hpp): what it covers, and every ISA against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "foam.hpp"
#include "houle/render/renderer.hpp"
#include "houle/runtime/isa.hpp"
#include "ulp.hpp"

namespace {

houle::SurfMap uniform_map(float foam, float dir_x, float dir_y, float amplitude) {
  houle::SurfMap m;
  m.origin_x = -20.0f, m.origin_y = 10.0f, m.cell = 2.0f, m.nx = 11, m.ny = 6;
  const std::size_t n = std::size_t(m.nx) * m.ny;
  m.foam.assign(n, foam), m.dir_x.assign(n, dir_x), m.dir_y.assign(n, dir_y), m.amplitude.assign(n, amplitude);
  return m;
}

struct Hits {
  std::vector<float> side, x, y, z, gx, gy, t;
  houle::detail::FoamInput input() const {
    return {side.data(), x.data(), y.data(), z.data(), gx.data(), gy.data(), t.data()};
  }
};

std::vector<float> cover_of(const houle::detail::PackedSurf& surf, const Hits& h, float pixel_angle,
                            houle::Isa isa = houle::Isa::scalar) {
  std::vector<float> c(h.x.size(), -7.0f);
  houle::detail::foam_cover(isa, surf.view(), h.input(), c.size(), pixel_angle, c.data());
  return c;
}

TEST(Foam, CrestsFrontsAndTheSpentSheetBetween) {
  // Foam 1 everywhere, waves travelling along +x with 1 m amplitude; a footprint of 1 m fades the
  // patches out (2 - 8 / 1.5 < 0), so the texture is 0.7: cover = 0.7 (0.2 + crest (0.3 + 0.7 front)).
  const houle::detail::PackedSurf surf = houle::detail::pack(uniform_map(1.0f, 1.0f, 0.0f, 1.0f));
  Hits h;
  const auto add = [&](float side, float x, float y, float z, float gx, float gy) {
    h.side.push_back(side), h.x.push_back(x), h.y.push_back(y), h.z.push_back(z), h.gx.push_back(gx), h.gy.push_back(gy);
    h.t.push_back(100.0f);
  };
  add(1.0f, -5.0f, 15.0f, 2.0f, -1.0f, 0.0f);    // on a crest, its front face (falling along +x): 0.7 1.2
  add(1.0f, -5.0f, 15.0f, 2.0f, 1.0f, 0.0f);     // on a crest, its back: 0.7 (0.2 + 0.3) = 0.35
  add(1.0f, -5.0f, 15.0f, -2.0f, -1.0f, 0.0f);   // in a trough: the sheet, 0.7 0.2 = 0.14
  add(1.0f, -21.0f, 15.0f, 2.0f, -1.0f, 0.0f);   // off the map: its nearest edge point's foam
  add(1.0f, -5.0f, 20.1f, 2.0f, -1.0f, 0.0f);    // off its far edge, likewise
  add(-1.0f, -5.0f, 15.0f, 2.0f, -1.0f, 0.0f);   // seen from below
  add(0.0f, -5.0f, 15.0f, 2.0f, -1.0f, 0.0f);    // no sea hit
  add(1.0f, std::numeric_limits<float>::quiet_NaN(), 15.0f, 2.0f, -1.0f, 0.0f);
  const std::vector<float> c = cover_of(surf, h, 0.01f);
  const float want[] = {0.84f, 0.35f, 0.14f, 0.84f, 0.84f, 0.0f, 0.0f, 0.0f};
  for (std::size_t k = 0; k < c.size(); ++k) EXPECT_NEAR(c[k], want[k], 1e-6f) << k;

  // At a wall's toe (no direction of travel) every crest foams whatever the slope.
  const houle::detail::PackedSurf toe = houle::detail::pack(uniform_map(1.0f, 0.0f, 0.0f, 1.0f));
  const std::vector<float> c_toe = cover_of(toe, h, 0.01f);
  ASSERT_EQ(c_toe.size(), h.x.size());
  EXPECT_NEAR(c_toe[1], 0.84f, 1e-6f);
  // Off the map a toe does not go on: the wall may end at the map's edge.
  EXPECT_EQ(c_toe[3], 0.0f);
  EXPECT_EQ(c_toe[4], 0.0f);
  // No foam in the map, none on the sea.
  for (float v : cover_of(houle::detail::pack(uniform_map(0.0f, 1.0f, 0.0f, 1.0f)), h, 0.01f)) EXPECT_EQ(v, 0.0f);
  // Near (a 1 cm footprint) the patches show: the texture varies within 0.7 +- 0.3, the cover with it.
  Hits near = h;
  near.t.assign(near.t.size(), 1.0f);
  float lo = 1.0f, hi = 0.0f;
  for (int k = 0; k < 200; ++k) {
    near.x[0] = -19.0f + 0.09f * float(k);
    const std::vector<float> c_near = cover_of(surf, near, 0.01f);
    ASSERT_FALSE(c_near.empty());
    const float v = c_near.front();
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  EXPECT_GE(lo, 0.4f * 1.2f - 1e-6f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(hi - lo, 0.2f);
}

TEST(Foam, ThinningFoamBreaksUpIntoLace) {
  // Foam 0.3 (carried behind a break): near, a coarse noise opens bare water between laces of
  // thicker foam; far (a 2 m footprint, where the lace would alias) it is an even sheet.
  const houle::detail::PackedSurf surf = houle::detail::pack(uniform_map(0.3f, 1.0f, 0.0f, 1.0f));
  Hits h;
  for (int k = 0; k < 400; ++k) {
    h.side.push_back(1.0f), h.x.push_back(-19.0f + 0.045f * float(k)), h.y.push_back(11.0f + 0.02f * float(k));
    h.z.push_back(2.0f), h.gx.push_back(-1.0f), h.gy.push_back(0.0f), h.t.push_back(10.0f);
  }
  const std::vector<float> near = cover_of(surf, h, 0.001f);
  const std::size_t bare = std::size_t(std::count(near.begin(), near.end(), 0.0f));
  const float thickest = *std::max_element(near.begin(), near.end());
  std::printf("foam 0.3 near: %zu of %zu bare, thickest %.3f (unlaced at most %.3f)\n", bare, near.size(), thickest, 0.3f * 1.2f);
  EXPECT_GT(bare, near.size() / 10);
  EXPECT_LT(bare, near.size() * 9 / 10);
  EXPECT_GT(thickest, 0.3f * 1.2f * 1.5f);
  h.t.assign(h.t.size(), 200.0f);
  for (float v : cover_of(surf, h, 0.01f)) EXPECT_NEAR(v, 0.3f * 0.7f * 1.2f, 1e-6f);
}

TEST(Foam, TheLaceHasNoPreferredAxis) {
  // Seen from above, lace cut from one axis-aligned value-noise lattice read as rows of squares
  // along the break line: its edges ran along the axes. Measured by where the cover's gradients
  // point: <cos 4 theta> weighted by |grad|^2 is 0 for edges in every direction, 1 for edges along
  // the axes alone. Foam 0.3 over 200 x 200 m sampled every 0.37 m, a 1 mm footprint (the lace at
  // full strength). One lattice gave 0.22; two turned 45 degrees apart cancel its cos 4 theta but for
  // what the clamp and this fourth-order measure add (0.05-0.06 over other 200 m squares).
  houle::SurfMap m = uniform_map(0.3f, 1.0f, 0.0f, 1.0f);
  m.origin_x = -110.0f, m.origin_y = -110.0f, m.cell = 40.0f, m.nx = 23, m.ny = 23;
  const std::size_t nodes = std::size_t(m.nx) * m.ny;
  m.foam.assign(nodes, 0.3f), m.dir_x.assign(nodes, 1.0f), m.dir_y.assign(nodes, 0.0f), m.amplitude.assign(nodes, 1.0f);
  const houle::detail::PackedSurf surf = houle::detail::pack(m);
  constexpr float e = 0.05f;
  const float offsets[4][2] = {{e, 0.0f}, {-e, 0.0f}, {0.0f, e}, {0.0f, -e}};
  Hits h;
  for (int j = 0; j < 540; ++j) {
    for (int i = 0; i < 540; ++i) {
      for (const auto& o : offsets) {
        h.side.push_back(1.0f), h.x.push_back(-100.0f + 0.37f * float(i) + o[0]), h.y.push_back(-100.0f + 0.37f * float(j) + o[1]);
        h.z.push_back(2.0f), h.gx.push_back(-1.0f), h.gy.push_back(0.0f), h.t.push_back(1.0f);
      }
    }
  }
  const std::vector<float> c = cover_of(surf, h, 0.001f);
  double sum = 0.0, weight = 0.0;
  for (std::size_t k = 0; k + 3 < c.size(); k += 4) {
    const double gx = double(c[k]) - double(c[k + 1]), gy = double(c[k + 2]) - double(c[k + 3]), g2 = gx * gx + gy * gy;
    if (!(g2 > 0.0)) continue;
    sum += (gx * gx * gx * gx - 6.0 * gx * gx * gy * gy + gy * gy * gy * gy) / g2;
    weight += g2;
  }
  std::printf("lace edges: <cos 4 theta> = %.3f\n", sum / weight);
  EXPECT_LT(std::fabs(sum / weight), 0.1);
}

TEST(Foam, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, exact conversions, integer hashing and gathers), but
  // for ARMv7 NEON, which flushes subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp.
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  houle::SurfMap m = uniform_map(0.0f, 0.0f, 0.0f, 0.0f);
  m.nx = 37, m.ny = 23, m.cell = 2.5f, m.origin_x = -30.0f, m.origin_y = 12.0f;
  const std::size_t nodes = std::size_t(m.nx) * m.ny;
  m.foam.resize(nodes), m.dir_x.resize(nodes), m.dir_y.resize(nodes), m.amplitude.resize(nodes);
  for (std::size_t n = 0; n < nodes; ++n) {
    m.foam[n] = n % 5 == 0 ? 0.0f : u(rng) * 1.5f;  // some cells without foam at all corners
    m.dir_x[n] = u(rng) * 2.0f - 1.0f, m.dir_y[n] = u(rng) * 2.0f - 1.0f, m.amplitude[n] = u(rng) * 2.0f;
  }
  const houle::detail::PackedSurf surf = houle::detail::pack(m);
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    std::size_t foamy = 0;
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
      Hits h;
      for (std::size_t k = 0; k < n; ++k) {
        h.side.push_back(k % 7 == 3 ? -1.0f : k % 11 == 4 ? 0.0f : 1.0f);
        // A margin of 5 m around the map, which covers [-30, 60] x [12, 67].
        h.x.push_back(k % 23 == 9 ? std::numeric_limits<float>::quiet_NaN() : -35.0f + 100.0f * u(rng));
        h.y.push_back(7.0f + 65.0f * u(rng));
        h.z.push_back(4.0f * u(rng) - 2.0f);
        h.gx.push_back(u(rng) - 0.5f), h.gy.push_back(u(rng) - 0.5f);
        h.t.push_back(std::exp(8.0f * u(rng)));  // 1 m to 3 km: patches and none
      }
      const std::vector<float> ref = cover_of(surf, h, 1e-3f), got = cover_of(surf, h, 1e-3f, isa);
      for (std::size_t k = 0; k < n; ++k) {
        foamy += ref[k] > 0.0f;
        if (!(std::fabs(ref[k] - got[k]) <= (isa == houle::Isa::neon ? 1e-6f : 0.0f))) {
          worst = std::max(worst, houle::test::ulp_distance(ref[k], got[k]));
        }
      }
    }
    EXPECT_GT(foamy, 300u);  // most of the lanes meet foam
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
    std::printf("foam_cover %s vs scalar: max %lld ulp (tolerance %lld)\n", houle::isa_name(isa).data(),
                static_cast<long long>(worst), static_cast<long long>(tolerance(isa)));
  }
}

}  // namespace
