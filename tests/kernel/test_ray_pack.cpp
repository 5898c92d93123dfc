// Secondary rays packed from a row of sea hits (kernel/render/src/ray_pack.hpp): which pixels send
// one, from where and along what, in pixel order; and every ISA against the scalar path, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "ray_pack.hpp"

namespace {

constexpr float pack_nan = std::numeric_limits<float>::quiet_NaN();

struct PackRow {
  std::vector<float> side, kr, t, x, y, z, nx, ny, nz, ax, ay, az, bx, by, bz;
  std::size_t size() const { return side.size(); }
  houle::detail::RayPackInput input() const {
    return {side.data(), kr.data(), t.data(), x.data(), y.data(), z.data(), nx.data(), ny.data(), nz.data(),
            ax.data(),   ay.data(), az.data(), bx.data(), by.data(), bz.data()};
  }
};

PackRow random_pack_row(std::mt19937& rng, std::size_t n) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const float sides[] = {0.0f, 1.0f, 1.0f, 1.0f, -1.0f};
  PackRow r;
  for (std::size_t i = 0; i < n; ++i) {
    r.side.push_back(sides[std::size_t(rng() % 5)]);
    // Mostly partly reflecting; some totally (kr 1), some NaN.
    const auto k = rng() % 10;
    r.kr.push_back(k == 0 ? 1.0f : k == 1 ? pack_nan : 0.5f + 0.4f * u(rng));
    r.t.push_back(100.0f * (u(rng) + 1.0f));
    for (auto* v : {&r.x, &r.y}) v->push_back(300.0f * u(rng));
    r.z.push_back(0.5f * u(rng));
    for (auto* v : {&r.nx, &r.ny, &r.nz, &r.ax, &r.ay, &r.az, &r.bx, &r.by, &r.bz}) v->push_back(u(rng));
  }
  return r;
}

struct PackedRays {
  std::vector<float> ox, oy, oz, dx, dy, dz, reach;
  std::vector<std::uint32_t> pixel;
  explicit PackedRays(std::size_t n) {
    const std::size_t padded = (n + 15) / 16 * 16;
    for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &reach}) v->assign(padded, -9.0f);
    pixel.assign(padded, 0xdeadbeef);
  }
  houle::detail::RayPackOutput output() {
    return {ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), reach.data(), pixel.data()};
  }
};

bool same_float_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(RayPack, SendsTheRaysOfSeaHitsButUnderTotalReflectionInPixelOrder) {
  std::mt19937 rng(5);
  const PackRow r = random_pack_row(rng, 301);
  for (bool into_water : {true, false}) {
    PackedRays got(r.size());
    const std::size_t count = houle::detail::pack_rays(houle::Isa::scalar, r.input(), r.size(), {into_water, 42.0f},
                                                       got.output());
    std::size_t k = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      // Into the water the refracted ray goes from above, into the air from below.
      const bool refracting = into_water ? r.side[i] > 0.0f : r.side[i] < 0.0f;
      if (r.side[i] == 0.0f || (refracting && !(r.kr[i] < 1.0f))) continue;
      ASSERT_LT(k, count);
      EXPECT_EQ(got.pixel[k], i);
      const float offset = 1e-3f + 1e-4f * r.t[i], s = into_water ? -1.0f : 1.0f;
      EXPECT_FLOAT_EQ(got.ox[k], r.x[i] + offset * s * r.nx[i]) << i;
      EXPECT_FLOAT_EQ(got.oy[k], r.y[i] + offset * s * r.ny[i]) << i;
      EXPECT_FLOAT_EQ(got.oz[k], r.z[i] + offset * s * r.nz[i]) << i;
      const bool above = r.side[i] > 0.0f;
      EXPECT_EQ(got.dx[k], above ? r.ax[i] : r.bx[i]) << i;
      EXPECT_EQ(got.dy[k], above ? r.ay[i] : r.by[i]) << i;
      EXPECT_EQ(got.dz[k], above ? r.az[i] : r.bz[i]) << i;
      EXPECT_EQ(got.reach[k], 42.0f);
      ++k;
    }
    EXPECT_EQ(count, k) << into_water;
    EXPECT_GT(count, r.size() / 3) << into_water;
  }
}

TEST(RayPack, EveryIsaMatchesScalarBitForBitIncludingTails) {
  // Stated tolerance: 0 ulp. Lanes are moved, not changed; the origin is one expression.
  std::mt19937 rng(11);
  for (std::size_t n : {std::size_t(1), std::size_t(3), std::size_t(16 * 4 + 3), std::size_t(8 * 37 + 5), std::size_t(640)}) {
    const PackRow r = random_pack_row(rng, n);
    for (bool into_water : {true, false}) {
      PackedRays want(n);
      const std::size_t count = houle::detail::pack_rays(houle::Isa::scalar, r.input(), n, {into_water, 7.0f}, want.output());
      for (houle::Isa isa : houle::supported_isas()) {
        PackedRays got(n);
        ASSERT_EQ(houle::detail::pack_rays(isa, r.input(), n, {into_water, 7.0f}, got.output()), count)
            << houle::isa_name(isa) << " n = " << n;
        std::size_t differ = 0;
        for (std::size_t k = 0; k < count; ++k) {
          differ += got.pixel[k] != want.pixel[k] || !same_float_bits(got.ox[k], want.ox[k]) ||
                    !same_float_bits(got.oy[k], want.oy[k]) || !same_float_bits(got.oz[k], want.oz[k]) ||
                    !same_float_bits(got.dx[k], want.dx[k]) || !same_float_bits(got.dy[k], want.dy[k]) ||
                    !same_float_bits(got.dz[k], want.dz[k]) || !same_float_bits(got.reach[k], want.reach[k]);
        }
        EXPECT_EQ(differ, 0u) << houle::isa_name(isa) << " n = " << n << " into water " << into_water;
      }
    }
  }
}

}  // namespace
