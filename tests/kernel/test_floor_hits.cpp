// The floor hits of secondary rays (kernel/render/src/floor_hits.hpp): against SceneObjects' walk in
// double, what it leaves to that walk, the object bounds it lets through, and every ISA against the
// scalar path.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "houle/runtime/isa.hpp"
#include "scene_objects.hpp"
#include "ulp.hpp"
#include "floor_hits.hpp"

namespace {

using houle::detail::SceneObjects;
using houle::detail::SceneRay;
using houle::detail::FloorGridView;
using houle::detail::ObjectBounds;

constexpr float no_hit = std::numeric_limits<float>::infinity();

/// A bumpy sea bed, 1.5 m cells from (-30, -20): hills of 2 m on a floor 6 m down, with noise; with
/// `objects`, boxes and spheres scattered over it, some turned, some above the sea.
SceneObjects bumpy_floor(bool objects = false) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.4f, 0.4f);
  houle::RenderScene s;
  for (int k = 0; objects && k < 40; ++k) {
    const std::array<float, 3> c{-20.0f + 100.0f * (u(rng) + 0.4f), -10.0f + 75.0f * (u(rng) + 0.4f), 5.0f * u(rng) - 2.0f};
    if (k % 3 == 0) {
      s.spheres.push_back({c, 1.0f + 2.0f * (u(rng) + 0.4f), {0.5f, 0.5f, 0.5f}});
    } else {
      s.boxes.push_back({c, {1.0f + 3.0f * (u(rng) + 0.4f), 0.5f + (u(rng) + 0.4f), 1.0f + 2.0f * (u(rng) + 0.4f)},
                         5.0f * u(rng), {0.5f, 0.5f, 0.5f}});
    }
  }
  s.floor.origin_x = -30.0f, s.floor.origin_y = -20.0f, s.floor.cell = 1.5f, s.floor.nx = 53, s.floor.ny = 41;
  for (std::uint32_t j = 0; j < s.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < s.floor.nx; ++i) {
      s.floor.z.push_back(float(2.0 * std::sin(0.15 * i) * std::cos(0.2 * j)) - 6.0f + u(rng));
    }
  }
  return SceneObjects::build(s).value();
}

struct FloorTestRays {
  std::vector<float> ox, oy, oz, dx, dy, dz, t_max;
  void add(float x, float y, float z, float ax, float ay, float az, float reach) {
    const float n = std::sqrt(ax * ax + ay * ay + az * az);
    ox.push_back(x), oy.push_back(y), oz.push_back(z), dx.push_back(ax / n), dy.push_back(ay / n), dz.push_back(az / n);
    t_max.push_back(reach);
  }
  std::size_t size() const { return ox.size(); }
  houle::detail::FloorRays input() const {
    return {ox.data(), oy.data(), oz.data(), dx.data(), dy.data(), dz.data(), t_max.data()};
  }
  SceneRay ray(std::size_t k) const { return {ox[k], oy[k], oz[k], dx[k], dy[k], dz[k]}; }
};

struct WaterOut {
  std::vector<float> t, nx, ny, nz, left, objects;
  explicit WaterOut(std::size_t n)
      : t(n, -7.0f), nx(n, -7.0f), ny(n, -7.0f), nz(n, -7.0f), left(n, -7.0f), objects(n, -7.0f) {}
  houle::detail::FloorHits output() { return {t.data(), nx.data(), ny.data(), nz.data(), left.data(), objects.data()}; }
};

WaterOut hits_of(const SceneObjects& o, const FloorTestRays& r, houle::Isa isa = houle::Isa::scalar) {
  WaterOut h(r.size());
  houle::detail::floor_hits(isa, o.floor_grid(), o.object_bounds(), r.input(), r.size(), h.output());
  return h;
}

/// Rays from a sea at z = 0 +- 0.5 over the grid and up to 40 m beyond it (where the edges extend), in
/// every direction: refracted ones down at 10 to 90 degrees below the horizon, or (`up`) reflected ones
/// at 3 to 80 degrees above it, from 3.5 to 6.5 m down, among the floor's hills (some start under
/// them).
void add_rays(FloorTestRays& r, std::mt19937& rng, std::size_t n, float reach, bool up = false) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t k = 0; k < n; ++k) {
    const float az = 6.2831853f * u(rng), el = up ? 0.05f + 1.35f * u(rng) : 0.17f + 1.4f * u(rng);
    const float x = -70.0f + 160.0f * u(rng), y = -60.0f + 140.0f * u(rng);
    r.add(x, y, up ? -6.5f + 3.0f * u(rng) : u(rng) - 0.5f, std::cos(az) * std::cos(el), std::sin(az) * std::cos(el),
          up ? std::sin(el) : -std::sin(el), reach);
  }
}

TEST(FloorHits, MeetsTheFloorWhereSceneObjectsWalkDoes) {
  // SceneObjects' walk (double; tests/kernel/test_renderer.cpp holds it to a dense march) is the
  // reference. Stated tolerance: the float walk's t within 4e-6 (1 + t) m of it (8.5e-7 seen), the
  // normal within 3e-5 per component (5.5e-6 seen); the same rays hit and miss (a reach cuts some).
  const SceneObjects o = bumpy_floor();
  for (bool up : {false, true}) {
    std::mt19937 rng(11);
    FloorTestRays r;
    add_rays(r, rng, 4000, 30.0f, up);
    const WaterOut h = hits_of(o, r);
    int met = 0, missed = 0, left = 0;
    for (std::size_t k = 0; k < r.size(); ++k) {
      if (h.left[k] > 0.0f) {  // only rays up so slowly that they leave the hills after 64 cells
        EXPECT_TRUE(up && r.dz[k] < 0.1f) << k;
        ++left;
        continue;
      }
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
    EXPECT_GT(met, up ? 1000 : 3000) << up;
    EXPECT_GT(missed, up ? 1000 : 50) << up;
    EXPECT_LT(left, up ? 100 : 1) << up;
  }
}

TEST(FloorHits, AnIslandBoundsTheWalkOfRaysUpFromTheSea) {
  // Rays up from a sea 10 m over a flat bed, at 1 to 6 degrees, leave the floor's height range (up to
  // an island's top, 3 m up) only after up to 170 cells: without the height bands half would be left
  // to SceneObjects. The band below a ray's lowest point bounds its walk to the island's box: none is
  // left, and every one meets the floor where SceneObjects' walk does (stated tolerance as above),
  // hundreds of them on the island, some grazing its sides.
  houle::RenderScene s;
  s.floor.origin_x = -100.0f, s.floor.origin_y = -100.0f, s.floor.cell = 1.0f, s.floor.nx = 201, s.floor.ny = 201;
  for (std::uint32_t j = 0; j < s.floor.ny; ++j) {
    for (std::uint32_t i = 0; i < s.floor.nx; ++i) {
      const double x = -100.0 + i, y = -100.0 + j;
      s.floor.z.push_back(float(-10.0 + 13.0 * std::exp(-(x * x + y * y) / 200.0)));
    }
  }
  const SceneObjects o = SceneObjects::build(s).value();
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  FloorTestRays r;
  for (int k = 0; k < 4000; ++k) {
    const float x = -60.0f + 120.0f * u(rng), y = -60.0f + 120.0f * u(rng);
    // Half of them towards the island, within 20 m of its centre either side.
    const float to = std::atan2(-y, -x) + (20.0f / std::hypot(x, y)) * (2.0f * u(rng) - 1.0f);
    const float az = k % 2 == 0 ? to : 6.2831853f * u(rng), el = (1.0f + 5.0f * u(rng)) * 0.0174533f;
    r.add(x, y, u(rng) - 0.5f, std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el), 1e5f);
  }
  const WaterOut h = hits_of(o, r);
  int met = 0, long_walks = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    // The cells from the start to the top of the height range (3 m), at most.
    long_walks += (3.0f - r.oz[k]) / r.dz[k] * (std::fabs(r.dx[k]) + std::fabs(r.dy[k])) > float(houle::detail::max_floor_steps);
    ASSERT_EQ(h.left[k], 0.0f) << k;
    const houle::detail::SurfaceHit want = o.intersect_secondary(r.ray(k), 0.0, double(r.t_max[k]));
    if (want.kind == houle::detail::HitKind::none) {
      EXPECT_EQ(h.t[k], no_hit) << k;
      continue;
    }
    ++met;
    ASSERT_LT(h.t[k], no_hit) << k;
    EXPECT_NEAR(h.t[k], want.t, 4e-6f * (1.0f + want.t)) << k;
  }
  EXPECT_GT(long_walks, 1500);
  EXPECT_GT(met, 300);
}

TEST(FloorHits, LeavesWhatItCannotWalkToSceneObjects) {
  const SceneObjects o = bumpy_floor();
  FloorTestRays r;
  r.add(0.0f, 0.0f, -5.0f, 1.0f, 0.0f, 0.2f, 100.0f);     // rising out of the hills within 64 cells
  r.add(0.0f, 0.0f, -5.0f, 1.0f, 0.0f, 0.0f, 100.0f);     // level: SceneObjects' walk
  r.add(-29.0f, 0.0f, 0.0f, 1.0f, 0.3f, -0.02f, 500.0f);  // down so slowly that 64 cells do not reach the floor
  r.add(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f, 0.0f);       // no reach: no ray
  r.add(0.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.0f, 3.0f);       // straight down, the floor beyond its reach
  r.add(0.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, -1.0f, 30.0f);
  const WaterOut h = hits_of(o, r);
  const float left[] = {0.0f, 1.0f, 1.0f, 0.0f, 0.0f, 1.0f};
  for (std::size_t k = 0; k < r.size(); ++k) EXPECT_EQ(h.left[k], left[k]) << k;
  EXPECT_EQ(h.t[3], no_hit);
  EXPECT_EQ(h.t[4], no_hit);
  // Without a floor nothing is met, and nothing is left; a floor too large for the kernel's indices
  // leaves every ray.
  WaterOut none(r.size()), large(r.size());
  houle::detail::floor_hits(houle::Isa::scalar, FloorGridView{}, ObjectBounds{}, r.input(), r.size(), none.output());
  houle::detail::floor_hits(houle::Isa::scalar, FloorGridView{.too_large = true}, ObjectBounds{}, r.input(), r.size(),
                            large.output());
  for (std::size_t k = 0; k < r.size(); ++k) {
    EXPECT_EQ(none.t[k], no_hit) << k;
    EXPECT_EQ(none.left[k], 0.0f) << k;
    EXPECT_EQ(none.objects[k], 0.0f) << k;
    EXPECT_EQ(large.left[k], k == 3 ? 0.0f : 1.0f) << k;  // all but the ray without a reach
  }
}

TEST(FloorHits, LetsThroughEveryRayThatMeetsAnObjectBeforeTheFloor) {
  // The bounds test says no only where SceneObjects finds no box or sphere before the floor's hit,
  // and says it to most rays that pass beside them; the walk below the bounds' boxes it lets a ray
  // through finds the walk from the root's hit, to the bit.
  const SceneObjects o = bumpy_floor(true);
  ASSERT_GT(o.object_bounds().count, 8);
  for (bool up : {false, true}) {
    std::mt19937 rng(5);
    FloorTestRays r;
    const float reach = up ? 1e5f : 30.0f;
    add_rays(r, rng, 4000, reach, up);
    const WaterOut h = hits_of(o, r);
    int met = 0, culled = 0, some_boxes = 0;
    for (std::size_t k = 0; k < r.size(); ++k) {
      if (h.left[k] > 0.0f) continue;
      const double t_end = double(std::min(h.t[k], reach));
      const houle::detail::SurfaceHit want = o.intersect_objects(r.ray(k), 0.0, t_end);
      const auto cut = std::uint32_t(h.objects[k]);
      ASSERT_EQ(float(cut), h.objects[k]) << k;
      if (want.kind != houle::detail::HitKind::none) {
        ++met;
        ASSERT_NE(cut, 0u) << k;
      }
      if (cut == 0) {
        ++culled;
        continue;
      }
      some_boxes += cut != (1u << o.object_bounds().count) - 1;
      const houle::detail::SurfaceHit got = o.intersect_objects(r.ray(k), 0.0, t_end, cut);
      EXPECT_EQ(got.kind, want.kind) << k;
      EXPECT_EQ(got.t, want.t) << k;
      EXPECT_EQ(got.index, want.index) << k;
      EXPECT_EQ(got.normal, want.normal) << k;
    }
    EXPECT_GT(met, 100) << up;
    EXPECT_GT(culled, 1000) << up;
    EXPECT_GT(some_boxes, 300) << up;  // rays let through to some of the boxes, not all
  }
  // Rays that graze a lone box (whose bounds are its own faces) within a millimetre of its edges, from
  // 10 m to 10 km away: every one that meets it is let through. (The float slab test got all of these
  // right even without its margin; the margin is there for what it cannot be shown to get right.)
  houle::RenderScene lone;
  lone.boxes.push_back({{1234.5f, -876.25f, 3.0f}, {2.0f, 0.75f, 1.5f}, 0.0f, {0.5f, 0.5f, 0.5f}});
  const SceneObjects box = SceneObjects::build(lone).value();
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  FloorTestRays r;
  for (int k = 0; k < 20000; ++k) {
    // A point within 1 mm of one of the box's edges, and a ray through it from afar.
    double p[3];
    const double half[3] = {2.0, 0.75, 1.5}, centre[3] = {1234.5, -876.25, 3.0};
    for (int a = 0; a < 3; ++a) p[a] = centre[a] + half[a] * (2.0 * u(rng) - 1.0);
    for (int a : {k % 3, (k + 1) % 3}) p[a] = centre[a] + (u(rng) < 0.5f ? -1.0 : 1.0) * half[a] + 2e-3 * (u(rng) - 0.5);
    const double az = 6.2831853 * u(rng), el = 1.4 * (2.0 * u(rng) - 1.0), far = 10.0 * std::pow(1000.0, u(rng));
    const double d[3] = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)};
    r.add(float(p[0] - far * d[0]), float(p[1] - far * d[1]), float(p[2] - far * d[2]), float(d[0]), float(d[1]),
          float(d[2]), 1e5f);
  }
  const WaterOut h = hits_of(box, r);
  int met = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (box.intersect_objects(r.ray(k), 0.0, 1e5).kind == houle::detail::HitKind::none) continue;
    ++met;
    EXPECT_EQ(h.objects[k], 1.0f) << k;
  }
  EXPECT_GT(met, 1500);
}

// A ray lying on a face of a node's bounds, parallel to it, gives 0 * inf = NaN there, and the walk
// keeps the node for a direction of +0 on that axis but drops it for -0. That loses nothing only
// because every box lies strictly inside its node's padded bounds: both signs must meet the same.
TEST(SceneObjects, ARayAlongAFaceOfTheBoundsMeetsTheSameWhateverTheSignOfItsZero) {
  houle::RenderScene s;
  s.boxes.push_back({{0.0f, 0.0f, 0.0f}, {2.0f, 1.0f, 1.0f}, 0.05f, {0.5f, 0.5f, 0.5f}});
  s.boxes.push_back({{3.9f, 0.1f, 0.2f}, {2.0f, 1.0f, 1.0f}, -0.05f, {0.5f, 0.5f, 0.5f}});
  s.boxes.push_back({{1.5f, 2.5f, 0.5f}, {1.0f, 1.0f, 1.5f}, 0.7f, {0.5f, 0.5f, 0.5f}});
  const SceneObjects o = SceneObjects::build(s).value();
  const ObjectBounds& b = o.object_bounds();
  ASSERT_GE(b.count, 2);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int met = 0, rays = 0;
  for (int k = 0; k < b.count; ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const float plane : {b.lo[k][axis], b.hi[k][axis]}) {
        for (int n = 0; n < 200; ++n, ++rays) {
          // On the plane, somewhere across the scene, moving along the other two axes only.
          double p[3] = {2.0 + 5.0 * u(rng), 1.0 + 4.0 * u(rng), 3.0 * u(rng)};
          double d[3] = {u(rng), u(rng), u(rng)};
          p[axis] = double(plane);
          d[axis] = 0.0;
          const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          SceneRay r{p[0] - 8.0 * d[0] / len, p[1] - 8.0 * d[1] / len, p[2] - 8.0 * d[2] / len,
                     d[0] / len, d[1] / len, d[2] / len};
          const auto plus = o.intersect_objects(r, 0.0, 100.0);
          (axis == 0 ? r.dx : axis == 1 ? r.dy : r.dz) = -0.0;
          const auto minus = o.intersect_objects(r, 0.0, 100.0);
          ASSERT_EQ(plus.kind, minus.kind) << k << " " << axis << " " << n;
          EXPECT_EQ(plus.t, minus.t) << k << " " << axis << " " << n;
          EXPECT_EQ(plus.index, minus.index) << k << " " << axis << " " << n;
          met += plus.kind != houle::detail::HitKind::none;
        }
      }
    }
  }
  // Rays on one node's face meet the other boxes: the comparison is not only of misses.
  EXPECT_GT(met, rays / 10);
}

TEST(FloorHits, SendsNoRayThroughTheWaterBetweenTwoWallsToTheWalk) {
  // A detached breakwater along y = 120 and a wall along x = 160 that starts 20 m north of it, each
  // of 2 m stone blocks (as make_render_scene draws walls): one box around both holds 45 x 80 m of
  // open water. Rays down through that water, and rays up out of it, none nearer than 3 m to a
  // block, must not be sent to SceneObjects' walk; rays down onto the blocks must.
  houle::RenderScene s;
  for (int k = 0; k < 25; ++k) s.boxes.push_back({{81.0f + 2.0f * float(k), 120.0f, 0.0f}, {1.0f, 2.0f, 2.0f}, 0.0f, {0.5f, 0.5f, 0.5f}});
  for (int k = 0; k < 30; ++k) s.boxes.push_back({{160.0f, 141.0f + 2.0f * float(k), 0.0f}, {2.0f, 1.0f, 2.0f}, 0.0f, {0.5f, 0.5f, 0.5f}});
  const SceneObjects o = SceneObjects::build(s).value();
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  FloorTestRays open, onto;
  while (open.size() < 2000) {
    const float x = 80.0f + 80.0f * u(rng), y = 118.0f + 82.0f * u(rng);
    const bool near_breakwater = x < 133.0f && y < 125.0f, near_wall = x > 155.0f && y > 136.0f;
    if (near_breakwater || near_wall) continue;
    open.add(x, y, 0.2f, 0.1f * (u(rng) - 0.5f), 0.1f * (u(rng) - 0.5f), open.size() % 2 == 0 ? -1.0f : 1.0f, 10.0f);
  }
  for (int k = 0; k < 200; ++k) onto.add(80.5f + 49.0f * u(rng), 118.5f + 3.0f * u(rng), 5.0f, 0.0f, 0.0f, -1.0f, 10.0f);
  const WaterOut h = hits_of(o, open), h_onto = hits_of(o, onto);
  for (std::size_t k = 0; k < open.size(); ++k) {
    ASSERT_EQ(o.intersect_objects(open.ray(k), 0.0, 10.0).kind, houle::detail::HitKind::none) << k;
    EXPECT_EQ(h.objects[k], 0.0f) << open.ox[k] << ", " << open.oy[k];
  }
  for (std::size_t k = 0; k < onto.size(); ++k) {
    ASSERT_NE(h_onto.objects[k], 0.0f) << k;
    const auto cut = std::uint32_t(h_onto.objects[k]);
    EXPECT_EQ(o.intersect_objects(onto.ray(k), 0.0, 10.0, cut).kind, houle::detail::HitKind::box) << k;
  }
}

TEST(FloorHits, EveryIsaMatchesScalarIncludingTails) {
  // Stated tolerance: 0 ulp (+, -, *, simd::div, simd::sqrt, gathers), but for ARMv7 NEON, which
  // flushes subnormals: 64 ulp or 1e-6 absolute, as in test_optics.cpp; which rays are left to
  // SceneObjects, and which may meet objects, is the same everywhere.
  const SceneObjects o = bumpy_floor(true);
  const auto tolerance = [](houle::Isa isa) -> std::int64_t { return isa == houle::Isa::neon ? 64 : 0; };
  for (houle::Isa isa : houle::supported_isas()) {
    if (isa == houle::Isa::scalar) continue;
    std::int64_t worst = 0;
    std::mt19937 rng(23);
    for (std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(7), std::size_t(16),
                          std::size_t(17), std::size_t(8 * 5 + 3), std::size_t(8 * 37 + 3), std::size_t(16 * 60 + 3)}) {
      FloorTestRays r;
      add_rays(r, rng, n / 2, 30.0f);
      add_rays(r, rng, n - n / 2, 1e5f, true);
      // Some level, some slow to descend, some without a reach.
      for (std::size_t k = 0; k < n; k += 7) r.dz[k] = k % 3 == 0 ? 0.0f : -0.01f;
      for (std::size_t k = 3; k < n; k += 11) r.t_max[k] = 0.0f;
      const WaterOut want = hits_of(o, r), got = hits_of(o, r, isa);
      for (std::size_t k = 0; k < n; ++k) {
        ASSERT_EQ(got.left[k], want.left[k]) << houle::isa_name(isa) << " " << k;
        ASSERT_EQ(got.objects[k], want.objects[k]) << houle::isa_name(isa) << " " << k;
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
