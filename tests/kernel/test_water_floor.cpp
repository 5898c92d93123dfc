// The floor hits of rays into the water (kernel/render/src/water_floor.hpp): against SceneObjects'
// walk in double, what it leaves to that walk, and every ISA against the scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "scene_objects.hpp"
#include "ulp.hpp"
#include "water_floor.hpp"

namespace {

using houle::detail::SceneObjects;
using houle::detail::SceneRay;
using houle::detail::WaterFloorView;

constexpr float no_hit = std::numeric_limits<float>::infinity();

/// A bumpy sea bed, 1.5 m cells from (-30, -20): hills of 2 m on a floor 6 m down, with noise.
SceneObjects bumpy_floor() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.4f, 0.4f);
  houle::RenderScene s;
  s.floor.origin_x = -30.0f, s.floor.origin_y = -20.0f, s.floor.cell = 1.5f, s.floor.nx = 53, s.floor.ny = 41;
  for (std::uint32_t j = 0; j < s.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < s.floor.nx; ++i) {
      s.floor.z.push_back(float(2.0 * std::sin(0.15 * i) * std::cos(0.2 * j)) - 6.0f + u(rng));
    }
  }
  return SceneObjects::build(s).value();
}

struct DownRays {
  std::vector<float> ox, oy, oz, dx, dy, dz, t_max;
  void add(float x, float y, float z, float ax, float ay, float az, float reach) {
    const float n = std::sqrt(ax * ax + ay * ay + az * az);
    ox.push_back(x), oy.push_back(y), oz.push_back(z), dx.push_back(ax / n), dy.push_back(ay / n), dz.push_back(az / n);
    t_max.push_back(reach);
  }
  std::size_t size() const { return ox.size(); }
  houle::detail::WaterRays input() const {
    return {ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t_max.data()};
  }
  SceneRay ray(std::size_t k) const { return {ox[k], oy[k], oz[k], dx[k], dy[k], dz[k]}; }
};

struct WaterOut {
  std::vector<float> t, nx, ny, nz, left;
  explicit WaterOut(std::size_t n) : t(n, -7.0f), nx(n, -7.0f), ny(n, -7.0f), nz(n, -7.0f), left(n, -7.0f) {}
  houle::detail::WaterHits output() { return {t.data(), nx.data(), ny.data(), nz.data(), left.data()}; }
};

WaterOut hits_of(const WaterFloorView& f, const DownRays& r, houle::Isa isa = houle::Isa::scalar) {
  WaterOut h(r.size());
  houle::detail::water_floor(isa, f, r.input(), r.size(), h.output());
  return h;
}

/// Refracted rays from just under a sea at z = 0 +- 0.5, down at 10 to 90 degrees below the horizon
/// in every direction, over the grid and up to 40 m beyond it (where the edges extend).
void add_refracted(DownRays& r, std::mt19937& rng, std::size_t n, float reach) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t k = 0; k < n; ++k) {
    const float az = 6.2831853f * u(rng), el = 0.17f + 1.4f * u(rng);
    r.add(-70.0f + 160.0f * u(rng), -60.0f + 140.0f * u(rng), u(rng) - 0.5f, std::cos(az) * std::cos(el),
          std::sin(az) * std::cos(el), -std::sin(el), reach);
  }
}

TEST(WaterFloor, MeetsTheFloorWhereSceneObjectsWalkDoes) {
  // SceneObjects' walk (double; tests/kernel/test_renderer.cpp holds it to a dense march) is the
  // reference. Stated tolerance: the float walk's t within 4e-6 (1 + t) m of it (8.5e-7 seen), the
  // normal within 3e-5 per component (5.5e-6 seen); the same rays hit and miss (a reach cuts some).
  const SceneObjects o = bumpy_floor();
  std::mt19937 rng(11);
  DownRays r;
  add_refracted(r, rng, 4000, 30.0f);
  const WaterOut h = hits_of(o.water_floor(), r);
  int met = 0, missed = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    ASSERT_EQ(h.left[k], 0.0f) << k;  // each descends, within 64 cells
    const houle::detail::SurfaceHit want = o.intersect_secondary(r.ray(k), 0.0, double(r.t_max[k]));
    if (want.kind == houle::detail::HitKind::none) {
      EXPECT_EQ(h.t[k], no_hit) << k;
      ++missed;
      continue;
    }
    ++met;
    ASSERT_LT(h.t[k], no_hit) << k;
    EXPECT_NEAR(h.t[k], want.t, 4e-6f * (1.0f + want.t)) << k;
    EXPECT_NEAR(h.nx[k], want.normal[0], 3e-5f) << k;
    EXPECT_NEAR(h.ny[k], want.normal[1], 3e-5f) << k;
    EXPECT_NEAR(h.nz[k], want.normal[2], 3e-5f) << k;
  }
  EXPECT_GT(met, 3000);
  EXPECT_GT(missed, 50);
}

TEST(WaterFloor, LeavesWhatItCannotWalkToSceneObjects) {
  const SceneObjects o = bumpy_floor();
  DownRays r;
  r.add(0.0f, 0.0f, -1.0f, 1.0f, 0.0f, 0.2f, 100.0f);     // rising: SceneObjects' walk
  r.add(0.0f, 0.0f, -1.0f, 1.0f, 0.0f, 0.0f, 100.0f);     // level: the same
  r.add(-29.0f, 0.0f, 0.0f, 1.0f, 0.3f, -0.02f, 500.0f);  // down so slowly that 64 cells do not reach the floor
  r.add(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f, 0.0f);       // no reach: no ray
  r.add(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f, 3.0f);       // straight down, the floor beyond its reach
  r.add(0.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, -1.0f, 30.0f);
  const WaterOut h = hits_of(o.water_floor(), r);
  const float left[] = {1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 1.0f};
  for (std::size_t k = 0; k < r.size(); ++k) EXPECT_EQ(h.left[k], left[k]) << k;
  EXPECT_EQ(h.t[3], no_hit);
  EXPECT_EQ(h.t[4], no_hit);
  // Without a floor nothing is met, and nothing is left.
  const WaterOut none = hits_of(WaterFloorView{}, r);
  for (std::size_t k = 0; k < r.size(); ++k) {
    EXPECT_EQ(none.t[k], no_hit) << k;
    EXPECT_EQ(none.left[k], 0.0f) << k;
  }
}

TEST(WaterFloor, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, simd::sqrt, gathers), but for ARMv7 NEON, which
  // flushes subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp; which rays are left to
  // SceneObjects is the same everywhere.
  const SceneObjects o = bumpy_floor();
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
      DownRays r;
      add_refracted(r, rng, n, 30.0f);
      // Some rising, some slow to descend, some without a reach.
      for (std::size_t k = 0; k < n; k += 7) r.dz[k] = k % 3 == 0 ? 0.1f : -0.01f;
      for (std::size_t k = 3; k < n; k += 11) r.t_max[k] = 0.0f;
      const WaterOut want = hits_of(o.water_floor(), r), got = hits_of(o.water_floor(), r, isa);
      for (std::size_t k = 0; k < n; ++k) {
        ASSERT_EQ(got.left[k], want.left[k]) << houle::isa_name(isa) << " " << k;
        if (want.left[k] > 0.0f) continue;
        for (const auto& [a, b] : {std::pair{want.t[k], got.t[k]}, std::pair{want.nx[k], got.nx[k]},
                                   std::pair{want.ny[k], got.ny[k]}, std::pair{want.nz[k], got.nz[k]}}) {
          if (!(a == b) && !(isa == houle::Isa::neon && std::fabs(a - b) <= 1e-6f)) {
            worst = std::max(worst, houle::test::ulp_distance(a, b));
          }
        }
      }
    }
    EXPECT_LE(worst, tolerance(isa)) << "ISA " << houle::isa_name(isa);
  }
}

}  // namespace
