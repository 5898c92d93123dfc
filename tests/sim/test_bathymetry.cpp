// Bathymetry: exact values where they are known, gradients against finite differences, C1 joins.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "houle/sim/bathymetry.hpp"

namespace {

using houle::Bathymetry;
using houle::SeaFloor;

SeaFloor beach() {
  SeaFloor f;
  f.base.kind = houle::FloorKind::planar_beach;
  f.base.depth = 10.0;
  f.base.slope = 0.05;
  f.base.shoreward_deg = 90.0;
  f.base.shoreline = {0.0, 100.0};
  return f;
}

SeaFloor everything() {
  SeaFloor f = beach();
  f.base.shoreward_deg = 70.0;
  f.shoals.push_back(houle::Shoal{{40.0, 30.0}, 15.0, 8.0, 25.0, 3.0});
  f.shoals.push_back(houle::Shoal{{70.0, 60.0}, 6.0, 6.0, 0.0, -2.0});
  f.bars.push_back(houle::Bar{{0.0, 70.0}, 5.0, 7.0, 1.2});
  f.channels.push_back(houle::Channel{{20.0, 10.0}, {60.0, 90.0}, 6.0, 1.5});
  houle::HeightMap m;
  m.nx = 9;
  m.ny = 7;
  m.origin = {-10.0, -5.0};
  m.cell = 12.5;
  m.mode = houle::HeightMapMode::additive;
  for (std::uint32_t j = 0; j < m.ny; ++j) {
    for (std::uint32_t i = 0; i < m.nx; ++i) m.depth.push_back(float(0.7 * std::sin(0.9 * i) * std::cos(1.3 * j)));
  }
  f.height_map = m;
  return f;
}

TEST(Bathymetry, FlatIsUniform) {
  const Bathymetry b{SeaFloor{}};
  EXPECT_TRUE(b.uniform());
  EXPECT_TRUE(std::isinf(b.length_scale()));
  const houle::DepthSample s = b.sample(12.0, -7.0);
  EXPECT_EQ(s.depth, 20.0);
  EXPECT_EQ(s.grad_x, 0.0);
  EXPECT_EQ(s.grad_y, 0.0);
  EXPECT_EQ(b.min_depth_bound(houle::Domain{}), 20.0);
}

TEST(Bathymetry, PlanarBeachIsExactOnTheSlopeAndC1AtThePlateau) {
  const Bathymetry b{beach()};
  EXPECT_FALSE(b.uniform());
  // On the plane (depth < 9 m: below the blend), h = slope * seaward distance, landward negative.
  for (double y : {-70.0, 0.0, 50.0, 99.0, 100.0, 120.0}) {
    const houle::DepthSample s = b.sample(3.0, y);
    EXPECT_NEAR(s.depth, 0.05 * (100.0 - y), 1e-12) << y;
    EXPECT_NEAR(s.grad_x, 0.0, 1e-15);
    EXPECT_NEAR(s.grad_y, -0.05, 1e-15);
  }
  // Far offshore: the plateau.
  EXPECT_EQ(b.depth(0.0, -500.0), 10.0);
  // Across the blend (raw depth 9 .. 11 m, y = -120 .. -80): depth and slope continuous.
  double prev_d = b.depth(0.0, -130.0), prev_g = b.sample(0.0, -130.0).grad_y;
  for (double y = -130.0; y <= -70.0; y += 0.01) {
    const houle::DepthSample s = b.sample(0.0, y);
    EXPECT_LE(std::fabs(s.depth - prev_d), 0.05 * 0.01 + 1e-12);
    EXPECT_LE(std::fabs(s.grad_y - prev_g), 0.05 * 0.01 / 1.0 + 1e-12);  // |d2h/dy2| <= slope^2 / (2 blend)
    EXPECT_LE(s.depth, 10.0);
    prev_d = s.depth;
    prev_g = s.grad_y;
  }
  EXPECT_NEAR(b.min_depth_bound(houle::Domain{0, 0, 50, 100}), 0.0, 1e-12);
}

TEST(Bathymetry, GradientMatchesFiniteDifferences) {
  const Bathymetry b{everything()};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(-30.0, 130.0), uy(-20.0, 110.0);
  const double e = 1e-5;
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const double x = ux(rng), y = uy(rng);
    const houle::DepthSample s = b.sample(x, y);
    const double gx = (b.depth(x + e, y) - b.depth(x - e, y)) / (2 * e);
    const double gy = (b.depth(x, y + e) - b.depth(x, y - e)) / (2 * e);
    worst = std::max({worst, std::fabs(gx - s.grad_x), std::fabs(gy - s.grad_y)});
  }
  // Central differences: O(e^2 h''') plus rounding 1e-16 * h / e ~ 1e-10; kinks would show as ~1e-1.
  EXPECT_LT(worst, 1e-6);
  std::printf("bathymetry gradient vs central differences: max abs diff %.2e\n", worst);
}

TEST(Bathymetry, FeaturesAreC1AcrossTheirRims) {
  // Walk straight lines across every rim in tiny steps: the gradient never jumps.
  const Bathymetry b{everything()};
  const double step = 1e-4;
  const double lines[][4] = {{40, 30, 60, 30}, {70, 50, 70, 70}, {0, 60, 0, 80}, {5, 10, 35, 10}, {-15, 40, 20, 40}};
  for (const auto& l : lines) {
    const int n = int(std::hypot(l[2] - l[0], l[3] - l[1]) / step);
    houle::DepthSample prev = b.sample(l[0], l[1]);
    for (int i = 1; i <= n; ++i) {
      const double t = double(i) / n;
      const houle::DepthSample s = b.sample(l[0] + t * (l[2] - l[0]), l[1] + t * (l[3] - l[1]));
      ASSERT_LT(std::hypot(s.grad_x - prev.grad_x, s.grad_y - prev.grad_y), 1e-2) << "line " << l[0] << "," << l[1];
      prev = s;
    }
  }
}

TEST(Bathymetry, HeightMapInterpolatesSamplesAndClampsOutside) {
  SeaFloor f;
  houle::HeightMap m;
  m.nx = 6;
  m.ny = 5;
  m.origin = {10.0, 20.0};
  m.cell = 2.0;
  // A linear field: Catmull-Rom reproduces it exactly away from the edges.
  for (std::uint32_t j = 0; j < m.ny; ++j) {
    for (std::uint32_t i = 0; i < m.nx; ++i) m.depth.push_back(float(3.0 + 0.5 * i - 0.25 * j));
  }
  f.height_map = m;
  const Bathymetry b{f};
  for (std::uint32_t j = 0; j < m.ny; ++j) {
    for (std::uint32_t i = 0; i < m.nx; ++i) {
      EXPECT_NEAR(b.depth(10.0 + 2.0 * i, 20.0 + 2.0 * j), m.depth[j * m.nx + i], 1e-6);
    }
  }
  const houle::DepthSample mid = b.sample(14.7, 23.1);
  EXPECT_NEAR(mid.depth, 3.0 + 0.5 * 2.35 - 0.25 * 1.55, 1e-6);
  EXPECT_NEAR(mid.grad_x, 0.25, 1e-6);
  EXPECT_NEAR(mid.grad_y, -0.125, 1e-6);
  // Outside: edge values, zero gradient across the clamped direction.
  const houle::DepthSample out = b.sample(0.0, 23.0);
  EXPECT_NEAR(out.depth, 3.0 - 0.25 * 1.5, 1e-6);
  EXPECT_EQ(out.grad_x, 0.0);
  EXPECT_EQ(b.length_scale(), 2.0);
}

TEST(Bathymetry, MinDepthBoundIsALowerBound) {
  const Bathymetry b{everything()};
  const houle::Domain d{-20.0, -10.0, 120.0, 100.0};
  const double bound = b.min_depth_bound(d);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ux(d.x_min, d.x_max), uy(d.y_min, d.y_max);
  for (int i = 0; i < 20000; ++i) ASSERT_GE(b.depth(ux(rng), uy(rng)), bound);
}

}  // namespace

// A floor of 1024 each of shoals, bars and channels is binned (a point visits only the features that
// reach it): its depth and gradient are those of the full sum to the bit, each feature added in
// order, at points in and around the features and far outside them.
TEST(Bathymetry, ManyFeaturesGiveTheFullSumToTheBit) {
  std::mt19937 rng(22);
  const auto u = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  SeaFloor f;
  f.base.kind = houle::FloorKind::planar_beach;
  for (int i = 0; i < 1024; ++i) {
    f.shoals.push_back({{u(-500, 500), u(-500, 500)}, u(0.5, 40), u(0.5, 40), u(-360, 360), u(-5, 5)});
    f.bars.push_back({{u(-500, 500), u(-500, 500)}, u(-360, 360), u(0.5, 20), u(-2, 2)});
    f.channels.push_back({{u(-500, 500), u(-500, 500)}, {u(-500, 500), u(-500, 500)}, u(0.5, 10), u(-3, 3)});
  }
  f.shoals[7].semi_axis_a = 3000.0;  // one reaching far beyond the others
  const Bathymetry all(f);
  // The reference: the base, then each feature's own contribution (over a zero base) added in order.
  SeaFloor base = f;
  base.shoals.clear(), base.bars.clear(), base.channels.clear();
  std::vector<Bathymetry> each;
  SeaFloor one;
  one.base.depth = 0.0;
  for (const houle::Shoal& s : f.shoals) one.shoals = {s}, each.emplace_back(one);
  one.shoals.clear();
  for (const houle::Bar& s : f.bars) one.bars = {s}, each.emplace_back(one);
  one.bars.clear();
  for (const houle::Channel& s : f.channels) one.channels = {s}, each.emplace_back(one);
  const Bathymetry base_only(base);
  int mismatches = 0;
  for (int n = 0; n < 4000; ++n) {
    const double x = n % 4 == 0 ? u(-5000, 5000) : u(-600, 600), y = n % 4 == 0 ? u(-5000, 5000) : u(-600, 600);
    houle::DepthSample want = base_only.sample(x, y);
    for (const Bathymetry& b : each) {
      const houle::DepthSample c = b.sample(x, y);
      want.depth += c.depth, want.grad_x += c.grad_x, want.grad_y += c.grad_y;
    }
    const houle::DepthSample got = all.sample(x, y);
    mismatches += got.depth != want.depth || got.grad_x != want.grad_x || got.grad_y != want.grad_y;
  }
  EXPECT_EQ(mismatches, 0);
}
